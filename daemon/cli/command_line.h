// The hand-written parser the subcommands used before CLI11 (lumar_command_line.cpp). Only
// `lumar bench --tracking` (tracking_bench_command.cpp) still uses it; it leaves the binary
// in issue 14, and this file, command_line.cpp and tests/unit/core/command_line_test.cpp go
// with it. Long options with a value ("--frames 30" or "--frames=30"), flags ("--json"),
// repeatable options and positional arguments; misuse throws UsageError.
#pragma once

#include <map>
#include <optional>
#include <string>
#include <vector>

#include "usage_error.h"

namespace lumar {

struct OptionSpec {
    std::string name; // without the leading "--"
    bool takesValue = true;
    bool repeatable = false;
};

class CommandLine {
public:
    // Parses args (without the program and subcommand names). "--help"/"-h" is always known.
    CommandLine(const std::vector<std::string>& args, const std::vector<OptionSpec>& specs);

    [[nodiscard]] bool helpRequested() const { return help_; }
    [[nodiscard]] bool has(const std::string& name) const { return values_.count(name) != 0; }
    [[nodiscard]] std::optional<std::string> value(const std::string& name) const;
    [[nodiscard]] std::vector<std::string> values(const std::string& name) const;
    [[nodiscard]] const std::vector<std::string>& positional() const { return positional_; }

    // Typed access; throws UsageError naming the option for a malformed or out-of-range value.
    [[nodiscard]] long integer(const std::string& name, long fallback, long min, long max) const;
    [[nodiscard]] double number(const std::string& name, double fallback, double min, double max) const;

private:
    bool help_ = false;
    std::map<std::string, std::vector<std::string>> values_;
    std::vector<std::string> positional_;
};

} // namespace lumar
