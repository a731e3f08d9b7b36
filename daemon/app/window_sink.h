// The desktop window a configuration asks for (`[output] sink = "window"`, or `lumar run
// --preview`): opened once per process, like the KMS display (a reload keeps it), on the
// Wayland compositor $WAYLAND_DISPLAY names where it is set (and lumar was built with
// Wayland), else on the X server $DISPLAY names (also a Wayland desktop's Xwayland).
#pragma once

#include <memory>

#include "config/config.h"
#include "gles_renderer/window/preview_window.h"

namespace lumar {

// The window, sized as the configured camera frame, or nullptr (with one warning naming what
// was missing) when no display server is reachable: the caller falls back to the headless
// sink. Throws RuntimeError when a server is there but EGL cannot draw on it.
std::unique_ptr<PreviewWindow> openPreviewWindow(const Config& config);

} // namespace lumar
