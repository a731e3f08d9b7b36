// OpenGL ES 3 contexts on EGL: a headless display for output without a window (no surface:
// the renderer draws into its own framebuffer objects) on a GPU's EGL device or Mesa's
// surfaceless platform, or the GBM platform with one window surface for a KMS display (the
// finished frame is copied into it and flipped).
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include <EGL/egl.h>

namespace lumar {

// An initialised EGLDisplay. eglTerminate does not count references, so every headless
// context in the process shares one instance (see surfaceless()).
class EglDisplay {
public:
    // The process' headless display, initialised on first use and terminated when the last
    // holder lets go. Where EGL lists a hardware device of another vendor than Mesa
    // (EGL_EXT_platform_device) that has surfaceless contexts, on that device: NVIDIA's
    // driver, for one, has no surfaceless platform, and through libglvnd Mesa's surfaceless
    // platform would draw with llvmpipe beside the GPU. Else Mesa's surfaceless platform (its
    // GPU driver, or llvmpipe without one), as always. The environment variable
    // LUMAR_EGL_PLATFORM=surfaceless or =device forces either (device: the first device,
    // software ones too). Throws RuntimeError when the platform is missing or the variable
    // names another.
    static std::shared_ptr<EglDisplay> surfaceless();
    // A display on EGL device `index` (eglQueryDevicesEXT's order) of the EGL_EXT_platform_device
    // platform. Not shared; for tests and tools that pick a device. Throws RuntimeError when
    // there is no such device or platform.
    static std::shared_ptr<EglDisplay> device(int index);
    // The EGL devices' extension strings (eglQueryDeviceStringEXT), in eglQueryDevicesEXT's
    // order; empty where EGL cannot enumerate devices.
    [[nodiscard]] static std::vector<std::string> deviceExtensions();
    // A display on the GBM platform of `gbmDevice` (a struct gbm_device*), for window
    // surfaces that KMS scans out. Not shared: it lives as long as its holders, who must let
    // go before the GBM device is destroyed. Throws RuntimeError.
    static std::shared_ptr<EglDisplay> gbm(void* gbmDevice);
    // A display on the X11 platform of `xlibDisplay` (a Display*), for a desktop window
    // (gles_renderer/window). Not shared; its holders let go before the X connection closes.
    // Throws RuntimeError.
    static std::shared_ptr<EglDisplay> x11(void* xlibDisplay);
    // A display on the Wayland platform of `wlDisplay` (a struct wl_display*), for a desktop
    // window on Wayland. Not shared; its holders let go before the connection closes.
    static std::shared_ptr<EglDisplay> wayland(void* wlDisplay);

    EglDisplay(EglDisplay&& other) noexcept;
    EglDisplay& operator=(EglDisplay&& other) noexcept;
    EglDisplay(const EglDisplay&) = delete;
    EglDisplay& operator=(const EglDisplay&) = delete;
    ~EglDisplay();

    [[nodiscard]] EGLDisplay handle() const { return display_; }
    [[nodiscard]] bool hasExtension(std::string_view name) const;
    // The Mesa DRI driver behind the display ("kms_swrast", "iris", "v3d"...:
    // EGL_MESA_query_driver); empty where EGL does not say.
    [[nodiscard]] const std::string& driverName() const { return driverName_; }
    // The DRM node of the device the display renders with (EGL_EXT_device_query with
    // EGL_EXT_device_drm, e.g. "/dev/dri/card1"); empty for a device without one (plain
    // swrast) or where EGL does not say.
    [[nodiscard]] const std::string& drmDeviceFile() const { return drmDeviceFile_; }
    // The platform it was made on: "surfaceless", "device", "GBM", "X11" or "Wayland".
    [[nodiscard]] const std::string& platformName() const { return platformName_; }
    [[nodiscard]] int majorVersion() const { return major_; }
    [[nodiscard]] int minorVersion() const { return minor_; }
    // GBM displays: the ES 3 window config whose native visual is the scan-out format (set by
    // EglWindowSurface); contexts use it where EGL_KHR_no_config_context is missing, so they
    // can draw to the window.
    [[nodiscard]] EGLConfig windowConfig() const { return windowConfig_; }
    void setWindowConfig(EGLConfig config) { windowConfig_ = config; }

private:
    EglDisplay() = default;
    void terminate();

    static std::shared_ptr<EglDisplay> initialise(EGLenum platform, void* nativeDisplay, const char* what);

    EGLDisplay display_ = EGL_NO_DISPLAY;
    EGLConfig windowConfig_ = nullptr;
    int major_ = 0, minor_ = 0;
    std::string extensions_;
    std::string driverName_;
    std::string drmDeviceFile_;
    std::string platformName_;
};

// The window config for a surface the renderer presents into (a KMS scan-out buffer, a
// desktop window): OpenGL ES 3 renderable, 8-bit red, green and blue. `rank` scores each
// candidate by its native visual id (a DRM format on GBM, an X visual on X11): negative
// rejects it, and the first of the highest score is taken. Throws RuntimeError naming
// `where` when the display has no such config or `rank` rejects them all (`rejectedWhy`).
EGLConfig chooseWindowConfig(EGLDisplay display, const std::function<int(EGLint nativeVisualId)>& rank,
                             const char* where, const char* rejectedWhy);

// An OpenGL ES 3.0 (or later, compatible) context with no surface. Make it current before
// any GL call; destroying it releases it from the thread first.
class EglContext {
public:
    // Throws RuntimeError "no OpenGL ES 3 context: ..." when one cannot be created.
    explicit EglContext(std::shared_ptr<EglDisplay> display);

    EglContext(EglContext&& other) noexcept;
    EglContext& operator=(EglContext&& other) noexcept;
    EglContext(const EglContext&) = delete;
    EglContext& operator=(const EglContext&) = delete;
    ~EglContext();

    // Cheap when already current (several renderers may share a thread). Keeps the surface
    // that is bound, if any: the renderer draws into its own framebuffers either way.
    void makeCurrent() const;
    // Binds `surface` for drawing and reading (a window surface of the same display).
    void makeCurrent(EGLSurface surface) const;
    [[nodiscard]] EGLContext handle() const { return context_; }

private:
    void destroy();

    std::shared_ptr<EglDisplay> display_;
    EGLContext context_ = EGL_NO_CONTEXT;
};

// An EGL window surface on a GBM surface (struct gbm_surface*) with the ES 3 config whose
// native visual is `gbmFormat`. Destroyed before its display, which it keeps alive.
class EglWindowSurface {
public:
    // Throws RuntimeError when no config matches the format or creation fails.
    EglWindowSurface(std::shared_ptr<EglDisplay> display, void* gbmSurface, uint32_t gbmFormat);
    EglWindowSurface(EglWindowSurface&& other) noexcept;
    EglWindowSurface& operator=(EglWindowSurface&& other) noexcept;
    EglWindowSurface(const EglWindowSurface&) = delete;
    EglWindowSurface& operator=(const EglWindowSurface&) = delete;
    ~EglWindowSurface();

    [[nodiscard]] EGLSurface handle() const { return surface_; }
    [[nodiscard]] const std::shared_ptr<EglDisplay>& display() const { return display_; }
    // eglSwapBuffers; throws RuntimeError on failure.
    void swapBuffers() const;

private:
    void destroy();

    std::shared_ptr<EglDisplay> display_;
    EGLSurface surface_ = EGL_NO_SURFACE;
};

} // namespace lumar
