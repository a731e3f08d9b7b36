// The subcommands of the lumar binary (DESIGN.md §2). Each takes the arguments after its
// name, writes its result to stdout, logs to stderr, and returns an exit code; InputError,
// RuntimeError and UsageError thrown out of them are turned into exit codes by main.
#pragma once

#include <string>
#include <vector>

namespace lumar {

using Args = std::vector<std::string>;

int renderCommand(const Args& args);
int runCommand(const Args& args);
int checkConfigCommand(const Args& args);
int detectCommand(const Args& args);
int benchCommand(const Args& args);
int trackingBenchCommand(const Args& args); // lumar bench --tracking
int probeCommand(const Args& args);
int calibrateCommand(const Args& args);

// Loads --config FILE if given, else the built-in default, and applies its log level unless
// --log-level overrides it.
struct Config;
class CommandLine;
Config configFromCommandLine(const CommandLine& cl);

} // namespace lumar
