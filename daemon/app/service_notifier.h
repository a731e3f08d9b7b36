// The systemd notify protocol (sd_notify(3)) for `lumar run`: READY=1 once the first frame is
// out, WATCHDOG=1 from the render loop while frames flow, STATUS= lines for `systemctl
// status`, and RELOADING=1 around a configuration reload. Without $NOTIFY_SOCKET (not started
// by systemd) every call is a cheap no-op.
#pragma once

#include <chrono>
#include <string>

namespace lumar {

class ServiceNotifier {
public:
    ServiceNotifier();

    void ready();
    void reloading();
    void status(const std::string& text);
    // Sends WATCHDOG=1 at most at half the interval systemd asked for ($WATCHDOG_USEC).
    void frameDone(std::chrono::steady_clock::time_point now);
    void stopping();

    [[nodiscard]] bool watchdogEnabled() const { return watchdogInterval_.count() > 0; }

private:
    void send(const std::string& message);

    bool enabled_ = false;
    bool ready_ = false;
    std::chrono::microseconds watchdogInterval_{0};
    std::chrono::steady_clock::time_point nextWatchdog_{};
};

} // namespace lumar
