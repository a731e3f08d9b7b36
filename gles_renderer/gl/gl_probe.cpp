#include "gles_renderer/gl/gl_probe.h"

#include <cstring>
#include <sstream>

#include <GLES3/gl3.h>

#include "gles_renderer/gl/dmabuf_image.h"
#include "gles_renderer/gl/egl_context.h"
#include "gles_renderer/gl/gl_check.h"

namespace lumar {
namespace {

// The extensions that change what lumar can do: zero-copy camera import, HDR render
// targets, fences for display pacing.
constexpr const char* kEglExtensions[] = {"EGL_MESA_platform_surfaceless",
                                          "EGL_KHR_surfaceless_context",
                                          "EGL_KHR_no_config_context",
                                          "EGL_EXT_image_dma_buf_import",
                                          "EGL_EXT_image_dma_buf_import_modifiers",
                                          "EGL_ANDROID_native_fence_sync",
                                          "EGL_MESA_platform_gbm"};
constexpr const char* kGlExtensions[] = {"GL_EXT_color_buffer_half_float", "GL_EXT_color_buffer_float",
                                         "GL_OES_EGL_image_external",      "GL_OES_EGL_image_external_essl3",
                                         "GL_OES_texture_float_linear",    "GL_EXT_texture_filter_anisotropic"};

std::string text(const char* s)
{
    return s ? s : "";
}

std::string glString(GLenum name)
{
    return text(reinterpret_cast<const char*>(glGetString(name)));
}

} // namespace

GlInfo probeGl()
{
    const auto display = EglDisplay::surfaceless();
    const EglContext context(display);
    context.makeCurrent();
    GlInfo info;
    info.eglVendor = text(eglQueryString(display->handle(), EGL_VENDOR));
    info.eglVersion = text(eglQueryString(display->handle(), EGL_VERSION));
    info.eglClientApis = text(eglQueryString(display->handle(), EGL_CLIENT_APIS));
    info.glVersion = glString(GL_VERSION);
    info.glRenderer = glString(GL_RENDERER);
    info.glslVersion = glString(GL_SHADING_LANGUAGE_VERSION);
    const std::string clientExtensions = text(eglQueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS));
    for (const char* name : kEglExtensions) {
        const bool client = (" " + clientExtensions + " ").find(std::string(" ") + name + " ") != std::string::npos;
        const bool present = display->hasExtension(name) || client;
        info.eglExtensions.emplace_back(name, present);
    }
    for (const char* name : kGlExtensions)
        info.glExtensions.emplace_back(name, hasGlExtension(name));
    info.eglPlatform = display->platformName();
    info.driverName = display->driverName();
    info.drmDevice = display->drmDeviceFile();
    info.cameraImport = dmabufImportUnavailableReason(*display);
    return info;
}

} // namespace lumar
