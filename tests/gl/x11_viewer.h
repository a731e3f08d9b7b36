// A test's own connection to an X server: what anyone looking at the screen sees, and what a
// window manager would do to a window. Xlib stays inside x11_viewer.cpp (its macros None,
// Bool and Status break gtest's and lumar's headers).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace lumar::test {

class X11Viewer {
public:
    explicit X11Viewer(const std::string& displayName);
    ~X11Viewer();
    X11Viewer(const X11Viewer&) = delete;
    X11Viewer& operator=(const X11Viewer&) = delete;

    [[nodiscard]] bool connected() const { return display_ != nullptr; }
    // The top-level window titled `name`, 0 when there is none.
    [[nodiscard]] unsigned long findWindow(const std::string& name) const;
    // The window's pixels as the X server holds them: RGB, row 0 at the top; empty on failure.
    [[nodiscard]] std::vector<uint8_t> grab(unsigned long window, int width, int height) const;
    // Asks the window to close as a window manager's close button does (WM_DELETE_WINDOW).
    void requestClose(unsigned long window) const;
    void resize(unsigned long window, int width, int height) const;
    // Sends the window a key press and release of the Latin-1 character `c`, as typing it would.
    void typeKey(unsigned long window, char c) const;
    void close();

private:
    void* display_ = nullptr; // Display*
};

} // namespace lumar::test
