#include "config_watcher.h"

#include <cerrno>
#include <cstring>

#include <sys/inotify.h>

#include "core/error.h"

namespace lumar {

ConfigWatcher::ConfigWatcher(const std::filesystem::path& file)
    : name_(file.filename().string()), inotify_(inotify_init1(IN_NONBLOCK | IN_CLOEXEC))
{
    if (!inotify_.valid())
        throw RuntimeError(std::string("inotify: ") + std::strerror(errno));
    const std::filesystem::path dir = file.has_parent_path() ? file.parent_path() : std::filesystem::path(".");
    if (inotify_add_watch(inotify_.get(), dir.c_str(), IN_CLOSE_WRITE | IN_MOVED_TO) < 0)
        throw RuntimeError(dir.string() + ": cannot watch for configuration changes: " + std::strerror(errno));
}

bool ConfigWatcher::changed()
{
    bool ours = false;
    alignas(inotify_event) char buffer[4096];
    for (;;) {
        const ssize_t n = ::read(inotify_.get(), buffer, sizeof buffer);
        if (n <= 0)
            return ours; // EAGAIN: nothing more pending
        for (ssize_t offset = 0; offset + ssize_t(sizeof(inotify_event)) <= n;) {
            const auto* event = reinterpret_cast<const inotify_event*>(buffer + offset);
            // A plain create is followed by the close-after-write that matters; renames and
            // writes are the events that mean "a complete new file is there".
            if (event->len > 0 && name_ == event->name && (event->mask & (IN_CLOSE_WRITE | IN_MOVED_TO)))
                ours = true;
            offset += ssize_t(sizeof(inotify_event)) + event->len;
        }
    }
}

} // namespace lumar
