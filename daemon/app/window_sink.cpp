#include "window_sink.h"

#include <cstdlib>

#include "core/log.h"
#include "gles_renderer/window/x11_window.h"
#ifdef LUMAR_HAVE_WAYLAND
#include "gles_renderer/window/wayland_window.h"
#endif

namespace lumar {

std::unique_ptr<PreviewWindow> openPreviewWindow(const Config& config)
{
    std::string why;
    const char* wayland = std::getenv("WAYLAND_DISPLAY");
    const bool onWayland = wayland && *wayland;
#ifdef LUMAR_HAVE_WAYLAND
    if (onWayland) {
        if (auto window = WaylandWindow::open("", "lumar", config.camera.width, config.camera.height, why))
            return window;
        why += "; ";
    }
#endif
    std::string x11Why;
    if (auto window = X11Window::open("", "lumar", config.camera.width, config.camera.height, x11Why))
        return window;
    why += x11Why;
#ifndef LUMAR_HAVE_WAYLAND
    if (onWayland)
        why += " (lumar was built without Wayland: a Wayland session needs Xwayland)";
#endif
    const std::string fallback =
        config.output.path.empty() ? "no output" : "the headless sink (" + config.output.path.string() + ")";
    LUMAR_LOG(Output, Warn) << "no display server for the preview window (" << why << "); falling back to " << fallback;
    return nullptr;
}

} // namespace lumar
