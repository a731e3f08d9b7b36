#include "command_line.h"
#include "commands.h"
#include "config/config.h"
#include "core/log.h"

namespace lumar {

Config configFromCommandLine(const CommandLine& cl)
{
    const auto file = cl.value("config");
    Config config = file ? loadConfig(*file) : defaultConfig();
    const std::string level = cl.value("log-level").value_or(config.logLevel);
    if (!log::configure(level))
        throw UsageError("bad log level '" + level + "' (e.g. info, or capture:debug,*:warn)");
    return config;
}

} // namespace lumar
