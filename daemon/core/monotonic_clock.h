// CLOCK_MONOTONIC in nanoseconds: the clock camera timestamps (V4L2, libcamera) and KMS page
// flip events are on, so capture-to-present latency is one subtraction.
#pragma once

#include <cstdint>
#include <ctime>

namespace lumar {

inline int64_t monotonicClockNs()
{
    timespec now{};
    clock_gettime(CLOCK_MONOTONIC, &now);
    return int64_t(now.tv_sec) * 1'000'000'000 + now.tv_nsec;
}

} // namespace lumar
