#include "core/log.h"

#include <algorithm>
#include <cctype>
#include <chrono>
#include <cstdio>
#include <mutex>
#include <string>
#include <vector>

namespace lumar::log {
namespace {

std::vector<Category*>& registry()
{
    static std::vector<Category*> all;
    return all;
}

std::mutex& registryMutex()
{
    static std::mutex m;
    return m;
}

const char* levelName(Level l)
{
    switch (l) {
    case Level::Debug:
        return "DEBUG";
    case Level::Info:
        return "INFO";
    case Level::Warn:
        return "WARN";
    case Level::Error:
        return "ERROR";
    case Level::Off:
        break;
    }
    return "?";
}

bool equalsIgnoreCase(std::string_view a, std::string_view b)
{
    return a.size() == b.size() && std::equal(a.begin(), a.end(), b.begin(), [](char x, char y) {
               return std::tolower(static_cast<unsigned char>(x)) == std::tolower(static_cast<unsigned char>(y));
           });
}

} // namespace

Category::Category(const char* name) : name_(name), level_(int(Level::Info))
{
    std::lock_guard lock(registryMutex());
    registry().push_back(this);
}

Line::~Line()
{
    using namespace std::chrono;
    const double t = duration<double>(steady_clock::now().time_since_epoch()).count();
    std::string text = stream_.str();
    char prefix[96];
    std::snprintf(prefix, sizeof prefix, "[%12.6f] %-5s %s: ", t, levelName(level_), category_.name());
    text.insert(0, prefix);
    text.push_back('\n');
    std::fwrite(text.data(), 1, text.size(), stderr);
}

bool parseLevel(std::string_view text, Level& out)
{
    static constexpr std::pair<std::string_view, Level> names[] = {{"debug", Level::Debug}, {"info", Level::Info},
                                                                   {"warn", Level::Warn},   {"warning", Level::Warn},
                                                                   {"error", Level::Error}, {"off", Level::Off}};
    for (const auto& [name, level] : names) {
        if (equalsIgnoreCase(text, name)) {
            out = level;
            return true;
        }
    }
    return false;
}

bool configure(std::string_view spec)
{
    // Parse everything first so that a bad spec changes nothing.
    std::vector<std::pair<std::string, Level>> rules;
    while (!spec.empty()) {
        const size_t comma = spec.find(',');
        std::string_view item = spec.substr(0, comma);
        spec = comma == std::string_view::npos ? std::string_view{} : spec.substr(comma + 1);
        if (item.empty())
            continue;
        const size_t colon = item.find(':');
        std::string_view name = colon == std::string_view::npos ? "*" : item.substr(0, colon);
        std::string_view levelText = colon == std::string_view::npos ? item : item.substr(colon + 1);
        Level level{};
        if (!parseLevel(levelText, level))
            return false;
        rules.emplace_back(std::string(name), level);
    }
    std::lock_guard lock(registryMutex());
    for (const auto& [name, level] : rules) {
        bool matched = false;
        for (Category* c : registry()) {
            if (name == "*" || equalsIgnoreCase(name, c->name())) {
                c->setLevel(level);
                matched = true;
            }
        }
        if (!matched)
            return false;
    }
    return true;
}

} // namespace lumar::log
