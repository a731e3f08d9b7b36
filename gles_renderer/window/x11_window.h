// A desktop window on X11 for the preview sink (`[output] sink = "window"`, `lumar run
// --preview`): an X window with an EGL window surface on EGL's X11 platform
// (EGL_KHR_platform_x11), no toolkit. The renderer creates its context on this window's EGL
// display and copies each finished frame into the window (SceneRenderer::present: scaled to
// fit with its aspect kept, black bars around), as it does for a KMS display: with a GPU the
// frame never leaves it.
//
// On a software rasteriser the frame is shown from shared memory instead (MIT-SHM): Mesa
// 22.3's EGL X11 swrast path (Debian 12) has no MIT-SHM — libEGL_mesa imports xcb_put_image
// and no xcb_shm_* — so every eglSwapBuffers pushed the whole frame through the X socket in
// PutImage requests: 59-64 ms a 1280x720 frame under Xvfb (the profile: kernel socket copies
// and memmove, not GL). Reading the frame back as B, G, R, X straight into a shared segment
// and one XShmPutImage costs a few ms (tests/tools/window_present_bench prints both). No
// environment switch changes Mesa's path (LIBGL_DRI3_DISABLE concerns DRI3, which Xvfb lacks
// anyway). Where MIT-SHM is missing or refused (a remote X server), the EGL swap is used.
//
// On a Wayland session (WAYLAND_DISPLAY set) the preview is a Wayland window instead
// (wayland_window.h); this one still serves a Wayland desktop through Xwayland where lumar
// was built without Wayland.
#pragma once

#include <memory>
#include <optional>
#include <string>
#include <utility>

#include "gles_renderer/gl/egl_context.h"
#include "gles_renderer/window/preview_window.h"

namespace lumar {

// How frames reach the window: Auto takes SharedMemory on a software rasteriser (Mesa's
// "swrast"/"kms_swrast" driver) where the server grants MIT-SHM, EglSwap otherwise.
enum class X11Presentation { Auto, EglSwap, SharedMemory };

class X11Window final : public PreviewWindow {
public:
    // A window of `width` x `height` titled `title` on the X server `displayName` names
    // (empty: $DISPLAY). nullptr, with `why` saying so, when no X server is reachable;
    // throws RuntimeError when one is but EGL cannot draw there. SharedMemory asked for but
    // refused by the server falls back to EglSwap (logged).
    static std::unique_ptr<X11Window> open(const std::string& displayName, const std::string& title, int width,
                                           int height, std::string& why,
                                           X11Presentation presentation = X11Presentation::Auto);
    ~X11Window() override;
    X11Window(const X11Window&) = delete;
    X11Window& operator=(const X11Window&) = delete;

    [[nodiscard]] const std::shared_ptr<EglDisplay>& eglDisplay() const override { return eglDisplay_; }
    [[nodiscard]] EGLSurface surface() const override { return surface_; }
    [[nodiscard]] int width() const override { return width_; }
    [[nodiscard]] int height() const override { return height_; }
    // Handles the window's events: a new size (the next frame fills it), a close request.
    // Throws RuntimeError when the X server connection was lost.
    void showSwapped() override;
    // With MIT-SHM presentation: the shared image, the window's size.
    [[nodiscard]] std::optional<CpuPixels> cpuPixels() override;
    [[nodiscard]] bool presentsFromMemory() const { return sharedMemory_; }
    struct SharedImage; // the MIT-SHM image (x11_window.cpp)

    // Sizes the window for frames of `width` x `height` (once the camera's size is known, and
    // when it changes) and asks the window manager to keep that aspect while resizing.
    void fitFrame(int width, int height) override;
    // Handles pending events without presenting (a paused camera still lets the window close).
    void pollEvents() override;
    // The user closed the window (the window manager's close button or WM_DELETE_WINDOW).
    [[nodiscard]] bool closeRequested() const override { return closeRequested_; }
    // The characters typed into the window since the last call (its key presses as Latin-1
    // text, e.g. "o" for the overlay's toggle); cleared by the call.
    [[nodiscard]] std::string takeTypedKeys() override { return std::exchange(typed_, {}); }
    // The X window id, for tests and tools that look at the window from outside.
    [[nodiscard]] unsigned long windowId() const { return window_; }
    [[nodiscard]] uint64_t framesShown() const { return framesShown_; }

private:
    X11Window() = default;
    void setAspectHint(int width, int height);

    struct XConnection;
    std::unique_ptr<XConnection> x_;     // closed last
    std::unique_ptr<SharedImage> image_; // MIT-SHM presentation: the frame, the window's size
    void* gc_ = nullptr;                 // the GC XShmPutImage draws with
    bool sharedMemory_ = false;
    int visualDepth_ = 0;
    void* visual_ = nullptr; // the window's Visual*
    unsigned long window_ = 0;
    unsigned long colormap_ = 0;
    unsigned long deleteMessage_ = 0; // the WM_DELETE_WINDOW atom
    std::shared_ptr<EglDisplay> eglDisplay_;
    EGLSurface surface_ = EGL_NO_SURFACE;
    int width_ = 0, height_ = 0;
    bool closeRequested_ = false;
    std::string typed_;
    uint64_t framesShown_ = 0;
};

} // namespace lumar
