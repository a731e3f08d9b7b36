// A private X server for tests: Xvfb on a display number it picks itself (-displayfd), killed
// when the test ends. Tests skip when Xvfb is not installed.
#pragma once

#include <cstdlib>
#include <string>

#include <poll.h>
#include <unistd.h>

#include "gl/child_server.h"

namespace lumar::test {

class XvfbServer {
public:
    [[nodiscard]] static bool installed() { return std::system("command -v Xvfb >/dev/null 2>&1") == 0; }

    // Starts Xvfb with one 24-bit screen of `width` x `height`; display() is empty when it
    // could not be started.
    explicit XvfbServer(int width = 1600, int height = 1200)
    {
        int fds[2];
        if (::pipe(fds) != 0)
            return;
        const std::string screen = std::to_string(width) + "x" + std::to_string(height) + "x24";
        const bool started = child_.start(
            {"Xvfb", "-displayfd", std::to_string(fds[1]), "-screen", "0", screen, "-nolisten", "tcp", "-noreset"}, {},
            "", fds[0]);
        ::close(fds[1]);
        // Xvfb writes the display number once it accepts connections.
        std::string number;
        pollfd p{fds[0], POLLIN, 0};
        while (started && ::poll(&p, 1, 20000) > 0) {
            char c = 0;
            if (::read(fds[0], &c, 1) != 1 || c == '\n')
                break;
            number += c;
        }
        ::close(fds[0]);
        if (!number.empty())
            display_ = ":" + number;
    }

    [[nodiscard]] const std::string& display() const { return display_; }

    void stop() { child_.stop(); }

private:
    ChildServer child_;
    std::string display_;
};

} // namespace lumar::test
