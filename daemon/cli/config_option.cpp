#include "commands.h"
#include "config/config.h"
#include "core/log.h"
#include "usage_error.h"

namespace lumar {

void configureLogLevel(const std::string& spec)
{
    if (!log::configure(spec))
        throw UsageError("bad log level '" + spec + "' (e.g. info, or capture:debug,*:warn)");
}

Config configFromOptions(const ConfigOptions& options)
{
    Config config = options.file ? loadConfig(*options.file) : defaultConfig();
    configureLogLevel(options.logLevel.value_or(config.logLevel));
    return config;
}

} // namespace lumar
