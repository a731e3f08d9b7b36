// How long this process has existed, for the start-up time `lumar run` reports: measured from
// the kernel's record of the process's creation, so the dynamic loader, static initialisers
// and everything before main() are counted too.
#pragma once

#include <optional>

namespace lumar {

// Milliseconds since the process was created (the start time in /proc/self/stat, in clock
// ticks of 10 ms on Linux, against CLOCK_BOOTTIME, which that start time counts in); nullopt
// where /proc is not readable.
std::optional<double> millisecondsSinceProcessStart();

} // namespace lumar
