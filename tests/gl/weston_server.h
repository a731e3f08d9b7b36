// A private Wayland compositor for tests: weston in a runtime directory of its own, killed when
// the test ends. Its kiosk shell makes every toplevel fill the one output, without decorations,
// so a window's size is the output's. Two backends:
// - headless (no GPU, no input devices): enough to see a client's buffers reach weston;
// - X11, inside a test's Xvfb (xvfb_server.h): weston's output is then an X window of the
//   output's size that shows exactly what weston composited (pixman renderer), read back with
//   X11Viewer as a user would see it, and X key events sent to that window reach weston's
//   Wayland clients as keyboard input.
// Tests skip when weston is not installed.
#pragma once

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

#include <stdlib.h>
#include <sys/stat.h>

#include "gl/child_server.h"

namespace lumar::test {

class WestonServer {
public:
    [[nodiscard]] static bool installed() { return std::system("command -v weston >/dev/null 2>&1") == 0; }

    // Starts weston with one `width` x `height` output, on its headless backend or, with
    // `x11Display` (":N"), as a window on that X server; socket() is empty when it could not be
    // started (within 30 s).
    explicit WestonServer(int width = 320, int height = 240, const std::string& x11Display = "")
    {
        char pattern[] = "/tmp/lumar-weston-XXXXXX";
        if (!::mkdtemp(pattern))
            return;
        runtimeDir_ = pattern;
        const std::string name = "wayland-lumar-test";
        std::vector<std::string> args{"weston",
                                      "--shell=kiosk-shell.so",
                                      "--socket=" + name,
                                      "--width=" + std::to_string(width),
                                      "--height=" + std::to_string(height),
                                      "--idle-time=0",
                                      "--no-config"};
        std::vector<std::string> added{"XDG_RUNTIME_DIR=" + runtimeDir_};
        if (x11Display.empty()) {
            args.emplace_back("--backend=headless-backend.so");
        } else {
            // pixman: the window holds the clients' pixels as they are, no GL in between.
            args.insert(args.end(), {"--backend=x11-backend.so", "--use-pixman"});
            added.push_back("DISPLAY=" + x11Display);
        }
        if (!child_.start(args, environmentWith(added, {"XDG_RUNTIME_DIR=", "WAYLAND_", "DISPLAY="}),
                          runtimeDir_ + "/weston.log"))
            return;
        // The socket appears once weston accepts clients.
        const std::string path = runtimeDir_ + "/" + name;
        const bool ready = waitUntil(
            [&] {
                struct stat st {};
                return (::stat(path.c_str(), &st) == 0 && S_ISSOCK(st.st_mode)) || !child_.running();
            },
            std::chrono::seconds(30));
        if (ready && child_.running()) {
            socket_ = path;
            name_ = name;
        }
    }
    ~WestonServer()
    {
        stop();
        if (!runtimeDir_.empty()) {
            std::error_code ignored;
            std::filesystem::remove_all(runtimeDir_, ignored);
        }
    }
    WestonServer(const WestonServer&) = delete;
    WestonServer& operator=(const WestonServer&) = delete;

    // The socket's absolute path (what wl_display_connect takes), empty when weston did not start.
    [[nodiscard]] const std::string& socket() const { return socket_; }
    // For a child process: XDG_RUNTIME_DIR and WAYLAND_DISPLAY.
    [[nodiscard]] const std::string& runtimeDir() const { return runtimeDir_; }
    [[nodiscard]] const std::string& name() const { return name_; }
    // The title of weston's output window on the X11 backend (the first output's).
    [[nodiscard]] static std::string x11WindowTitle() { return "Weston Compositor - screen0"; }

    void stop() { child_.stop(); }

private:
    ChildServer child_; // stopped before the runtime directory goes
    std::string runtimeDir_;
    std::string socket_;
    std::string name_;
};

} // namespace lumar::test
