// Per-module log categories with levels (libcamera's model, much reduced). Library code logs
// through LUMAR_LOG only; it never writes to stdout, which belongs to a subcommand's output.
//
//   LUMAR_LOG(Capture, Info) << "opened " << path;
//
// Levels are set per category from a spec such as "info", "capture:debug,render:warn" or
// "*:warn,tracking:debug" (the --log-level option or the LUMAR_LOG environment variable).
#pragma once

#include <atomic>
#include <sstream>
#include <string>
#include <string_view>

namespace lumar::log {

enum class Level : int { Debug = 0, Info = 1, Warn = 2, Error = 3, Off = 4 };

class Category {
public:
    explicit Category(const char* name);
    [[nodiscard]] const char* name() const { return name_; }
    [[nodiscard]] bool enabled(Level l) const { return int(l) >= level_.load(std::memory_order_relaxed); }
    void setLevel(Level l) { level_.store(int(l), std::memory_order_relaxed); }

private:
    const char* name_;
    std::atomic<int> level_;
};

// One log line, written to stderr atomically when it goes out of scope.
class Line {
public:
    Line(const Category& c, Level l) : category_(c), level_(l) {}
    Line(const Line&) = delete;
    Line& operator=(const Line&) = delete;
    ~Line();
    std::ostream& stream() { return stream_; }

private:
    const Category& category_;
    Level level_;
    std::ostringstream stream_;
};

// Applies a level spec (see above). Returns false and leaves levels unchanged on a bad spec.
bool configure(std::string_view spec);
bool parseLevel(std::string_view text, Level& out);

} // namespace lumar::log

#define LUMAR_LOG_CATEGORY(Name)                                                                                       \
    namespace lumar::log::categories {                                                                                 \
    inline ::lumar::log::Category Name{#Name};                                                                         \
    }

// A one-pass loop rather than if/else, so that `if (x) LUMAR_LOG(...) << y;` has no dangling
// else, and the stream expression is not evaluated when the level is off.
#define LUMAR_LOG(Name, Lvl)                                                                                           \
    for (bool lumarLogOnce = ::lumar::log::categories::Name.enabled(::lumar::log::Level::Lvl); lumarLogOnce;           \
         lumarLogOnce = false)                                                                                         \
    ::lumar::log::Line(::lumar::log::categories::Name, ::lumar::log::Level::Lvl).stream()

// The categories of the whole program, declared once so every module shares them.
LUMAR_LOG_CATEGORY(App)
LUMAR_LOG_CATEGORY(Config)
LUMAR_LOG_CATEGORY(Capture)
LUMAR_LOG_CATEGORY(Tracking)
LUMAR_LOG_CATEGORY(Render)
LUMAR_LOG_CATEGORY(Output)
