// lumar's one error model: exceptions, caught at the stage boundary (a subcommand's main,
// the app loop's per-frame step, a config reload). Two kinds only, because the process
// exit code and the daemon's reaction differ: bad input (exit 2, keep the last good state)
// versus a runtime failure of the system underneath (exit 1).
#pragma once

#include <stdexcept>
#include <string>

namespace lumar {

// Something the user gave us is wrong: a config value, a file's content, a command-line
// argument. The message is one line and names the file (and line where known), e.g.
// "scene.toml:12: objects[0].marker: expected an integer".
class InputError : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

// The platform failed us: no EGL/GLES 3, a device error, out of memory, an I/O error on
// an output file.
class RuntimeError : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

// Exit codes shared by every subcommand (DESIGN.md §2).
enum ExitCode : int { kExitOk = 0, kExitRuntime = 1, kExitBadInput = 2 };

} // namespace lumar
