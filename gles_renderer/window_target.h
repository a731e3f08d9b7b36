// Where SceneRenderer::present() puts a finished frame: an EGL window surface on the
// renderer's display and what follows the swap (a KMS page flip). DESIGN.md §3 DisplaySink.
#pragma once

#include <memory>

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
    // Called after eglSwapBuffers: shows the new front buffer. Throws RuntimeError.
    virtual void showSwapped() = 0;
};

} // namespace lumar
