#include "command_line.h"

#include <cerrno>
#include <cmath>
#include <cstdlib>

namespace lumar {

CommandLine::CommandLine(const std::vector<std::string>& args, const std::vector<OptionSpec>& specs)
{
    auto findSpec = [&](const std::string& name) -> const OptionSpec* {
        for (const OptionSpec& s : specs)
            if (s.name == name)
                return &s;
        return nullptr;
    };

    for (size_t i = 0; i < args.size(); ++i) {
        const std::string& arg = args[i];
        if (arg == "--help" || arg == "-h") {
            help_ = true;
            continue;
        }
        if (arg.rfind("--", 0) != 0 || arg.size() == 2) {
            positional_.push_back(arg);
            continue;
        }
        std::string name = arg.substr(2);
        std::optional<std::string> inlineValue;
        if (const size_t eq = name.find('='); eq != std::string::npos) {
            inlineValue = name.substr(eq + 1);
            name.resize(eq);
        }
        const OptionSpec* spec = findSpec(name);
        if (!spec)
            throw UsageError("unknown option --" + name);
        std::string value;
        if (spec->takesValue) {
            if (inlineValue) {
                value = *inlineValue;
            } else {
                if (i + 1 >= args.size())
                    throw UsageError("option --" + name + " needs a value");
                value = args[++i];
            }
        } else if (inlineValue) {
            throw UsageError("option --" + name + " takes no value");
        }
        auto& slot = values_[name];
        if (!slot.empty() && !spec->repeatable)
            throw UsageError("option --" + name + " given more than once");
        slot.push_back(std::move(value));
    }
}

std::optional<std::string> CommandLine::value(const std::string& name) const
{
    const auto it = values_.find(name);
    if (it == values_.end())
        return std::nullopt;
    return it->second.front();
}

std::vector<std::string> CommandLine::values(const std::string& name) const
{
    const auto it = values_.find(name);
    return it == values_.end() ? std::vector<std::string>{} : it->second;
}

long CommandLine::integer(const std::string& name, long fallback, long min, long max) const
{
    const auto text = value(name);
    if (!text)
        return fallback;
    errno = 0;
    char* end = nullptr;
    const long v = std::strtol(text->c_str(), &end, 10);
    if (text->empty() || *end != '\0' || errno == ERANGE)
        throw UsageError("option --" + name + ": '" + *text + "' is not an integer");
    if (v < min || v > max)
        throw UsageError("option --" + name + ": " + *text + " is outside [" + std::to_string(min) + ", " +
                         std::to_string(max) + "]");
    return v;
}

double CommandLine::number(const std::string& name, double fallback, double min, double max) const
{
    const auto text = value(name);
    if (!text)
        return fallback;
    char* end = nullptr;
    const double v = std::strtod(text->c_str(), &end);
    if (text->empty() || *end != '\0' || !std::isfinite(v))
        throw UsageError("option --" + name + ": '" + *text + "' is not a number");
    if (v < min || v > max)
        throw UsageError("option --" + name + ": " + *text + " is outside the allowed range");
    return v;
}

} // namespace lumar
