// A headless OpenGL ES 3 context: Mesa's surfaceless EGL platform, no window and no
// surface (the renderer draws into its own framebuffer objects).
#pragma once

#include <memory>
#include <string>
#include <string_view>

#include <EGL/egl.h>

namespace lumar {

// An initialised EGLDisplay on the surfaceless platform. eglTerminate does not count
// references, so every context in the process shares one instance (see surfaceless()).
class EglDisplay {
public:
    // The process' surfaceless display, initialised on first use and terminated when the
    // last holder lets go. Throws RuntimeError when the platform is missing.
    static std::shared_ptr<EglDisplay> surfaceless();

    EglDisplay(EglDisplay&& other) noexcept;
    EglDisplay& operator=(EglDisplay&& other) noexcept;
    EglDisplay(const EglDisplay&) = delete;
    EglDisplay& operator=(const EglDisplay&) = delete;
    ~EglDisplay();

    [[nodiscard]] EGLDisplay handle() const { return display_; }
    [[nodiscard]] bool hasExtension(std::string_view name) const;
    [[nodiscard]] int majorVersion() const { return major_; }
    [[nodiscard]] int minorVersion() const { return minor_; }

private:
    EglDisplay() = default;
    void terminate();

    EGLDisplay display_ = EGL_NO_DISPLAY;
    int major_ = 0, minor_ = 0;
    std::string extensions_;
};

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

    // Cheap when already current (several renderers may share a thread).
    void makeCurrent() const;
    [[nodiscard]] EGLContext handle() const { return context_; }

private:
    void destroy();

    std::shared_ptr<EglDisplay> display_;
    EGLContext context_ = EGL_NO_CONTEXT;
};

} // namespace lumar
