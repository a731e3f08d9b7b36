#include "service_notifier.h"

#include <cstdlib>

#include <systemd/sd-daemon.h>

#include "core/log.h"

namespace lumar {

ServiceNotifier::ServiceNotifier() : enabled_(std::getenv("NOTIFY_SOCKET") != nullptr)
{
    uint64_t usec = 0;
    if (enabled_ && sd_watchdog_enabled(0, &usec) > 0)
        watchdogInterval_ = std::chrono::microseconds(usec / 2);
}

void ServiceNotifier::send(const std::string& message)
{
    if (!enabled_)
        return;
    const int rc = sd_notify(0, message.c_str());
    if (rc < 0)
        LUMAR_LOG(App, Warn) << "sd_notify failed: error " << -rc;
}

void ServiceNotifier::ready()
{
    ready_ = true;
    send("READY=1");
}

void ServiceNotifier::reloading()
{
    send("RELOADING=1");
}

void ServiceNotifier::status(const std::string& text)
{
    send("STATUS=" + text);
}

void ServiceNotifier::frameDone(std::chrono::steady_clock::time_point now)
{
    if (!ready_)
        ready();
    if (watchdogInterval_.count() > 0 && now >= nextWatchdog_) {
        send("WATCHDOG=1");
        nextWatchdog_ = now + watchdogInterval_;
    }
}

void ServiceNotifier::stopping()
{
    send("STOPPING=1");
}

} // namespace lumar
