// A desktop window for the preview sink (`[output] sink = "window"`, `lumar run --preview`),
// whatever the display server: an X11 window (x11_window.h) or a Wayland xdg-shell toplevel
// (wayland_window.h). The run loop sizes it, polls it, and reads the keys typed into it and
// whether the user closed it, without knowing which.
#pragma once

#include <string>

#include "gles_renderer/gl/window_target.h"

namespace lumar {

class PreviewWindow : public WindowTarget {
public:
    // Sizes the window for frames of `width` x `height` (once the camera's size is known, and
    // when it changes).
    virtual void fitFrame(int width, int height) = 0;
    // Handles pending events without presenting (a paused camera still lets the window close).
    // Throws RuntimeError when the display server went away.
    virtual void pollEvents() = 0;
    // The user closed the window (a window manager's close button, a compositor's close).
    [[nodiscard]] virtual bool closeRequested() const = 0;
    // The characters typed into the window since the last call (its key presses as text, e.g.
    // "o" for the overlay's toggle); cleared by the call.
    [[nodiscard]] virtual std::string takeTypedKeys() = 0;
};

} // namespace lumar
