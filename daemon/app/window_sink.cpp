#include "window_sink.h"

#include <cstdlib>

#include "core/log.h"

namespace lumar {

std::unique_ptr<X11Window> openPreviewWindow(const Config& config)
{
    std::string why;
    auto window = X11Window::open("", "lumar", config.camera.width, config.camera.height, why);
    if (!window) {
        if (const char* wayland = std::getenv("WAYLAND_DISPLAY"); wayland && *wayland)
            why += " (a Wayland session needs Xwayland: lumar's window is an X11 client)";
        const std::string fallback =
            config.output.path.empty() ? "no output" : "the headless sink (" + config.output.path.string() + ")";
        LUMAR_LOG(Output, Warn) << "no display server for the preview window (" << why << "); falling back to "
                                << fallback;
    }
    return window;
}

} // namespace lumar
