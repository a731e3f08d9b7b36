// A small command-line parser shared by the subcommands: long options with a value
// ("--frames 30" or "--frames=30"), flags ("--json"), repeatable options and positional
// arguments. Misuse throws UsageError, which main turns into exit code 2 and a hint.
#pragma once

#include <map>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

namespace lumar {

class UsageError : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

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
