// The lumar command line: every command with its options, help and checks, parsed by CLI11,
// and the outermost error boundary (DESIGN.md §2): --help exits 0 with the help on stdout;
// bad usage or bad input exits 2, a runtime failure exits 1, each with one line on stderr.
#pragma once

#include <string>
#include <vector>

namespace lumar {

// Runs `lumar ARGS...` (ARGS without the program name) and returns the process's exit code.
int lumarMain(const std::vector<std::string>& args);

} // namespace lumar
