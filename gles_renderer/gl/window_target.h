// Where SceneRenderer::present() puts a finished frame: an EGL window surface on the
// renderer's display and what follows the swap (a KMS page flip). DESIGN.md §3 DisplaySink.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>

#include <EGL/egl.h>

namespace lumar {

class EglDisplay;

class WindowTarget {
public:
    virtual ~WindowTarget() = default;
    // The display the surface belongs to: renderers presenting here create their context on it.
    [[nodiscard]] virtual const std::shared_ptr<EglDisplay>& eglDisplay() const = 0;
    [[nodiscard]] virtual EGLSurface surface() const = 0;
    [[nodiscard]] virtual int width() const = 0;
    [[nodiscard]] virtual int height() const = 0;
    // True when rendering must be finished (glFinish) before the swap: the display cannot wait
    // for the GPU itself (no implicit sync of the scan-out buffer, no native fence FD).
    [[nodiscard]] virtual bool finishBeforeSwap() const { return false; }
    // Called after eglSwapBuffers, or after the frame was written into cpuPixels(): shows the
    // new frame. Throws RuntimeError.
    virtual void showSwapped() = 0;

    // A target shown from CPU memory instead of an EGL surface (an X11 window on a software
    // rasteriser, through MIT-SHM: gles_renderer/window/x11_window.h says why): the renderer
    // writes the frame fitted to width() x height() there, as 32-bit pixels B, G, R, X in
    // memory, row 0 the top, `stride` bytes apart, then calls showSwapped(). nullopt: the frame
    // goes through surface() and eglSwapBuffers. Valid until the next showSwapped().
    struct CpuPixels {
        uint8_t* data = nullptr;
        int stride = 0;
    };
    [[nodiscard]] virtual std::optional<CpuPixels> cpuPixels() { return std::nullopt; }

    // A frame that reached the screen during the latest showSwapped(), for capture-to-present
    // latency: when it appeared (CLOCK_MONOTONIC, a KMS page flip's event time) and how many
    // swaps before the latest it was handed over (0: that swap's own frame; 1: the one before,
    // whose flip completed while this one was queued). nullopt: none, or the target cannot tell.
    struct Presentation {
        int64_t shownNs = 0;
        int swapsAgo = 0;
    };
    [[nodiscard]] virtual std::optional<Presentation> presentedDuringLastSwap() const { return std::nullopt; }
};

} // namespace lumar
