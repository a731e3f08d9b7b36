#include "gles_renderer/gl/egl_context.h"

#include <algorithm>
#include <cstdlib>
#include <mutex>
#include <utility>
#include <vector>

#include <EGL/eglext.h>

#include "core/error.h"
#include "core/log.h"

namespace lumar {
namespace {

bool extensionListHas(std::string_view list, std::string_view name)
{
    // Names are separated by single spaces; match whole words only (EGL_KHR_image vs
    // EGL_KHR_image_base).
    size_t pos = 0;
    while ((pos = list.find(name, pos)) != std::string_view::npos) {
        const bool startOk = pos == 0 || list[pos - 1] == ' ';
        const size_t end = pos + name.size();
        const bool endOk = end == list.size() || list[end] == ' ';
        if (startOk && endOk)
            return true;
        pos = end;
    }
    return false;
}

std::string eglErrorName(EGLint error)
{
    switch (error) {
    case EGL_NOT_INITIALIZED:
        return "EGL_NOT_INITIALIZED";
    case EGL_BAD_ACCESS:
        return "EGL_BAD_ACCESS";
    case EGL_BAD_ALLOC:
        return "EGL_BAD_ALLOC";
    case EGL_BAD_ATTRIBUTE:
        return "EGL_BAD_ATTRIBUTE";
    case EGL_BAD_CONFIG:
        return "EGL_BAD_CONFIG";
    case EGL_BAD_CONTEXT:
        return "EGL_BAD_CONTEXT";
    case EGL_BAD_DISPLAY:
        return "EGL_BAD_DISPLAY";
    case EGL_BAD_MATCH:
        return "EGL_BAD_MATCH";
    case EGL_BAD_PARAMETER:
        return "EGL_BAD_PARAMETER";
    default:
        return "EGL error " + std::to_string(error);
    }
}

// The DRI driver's name, where EGL_MESA_query_driver is there.
std::string queryDriverName(EGLDisplay display, std::string_view extensions)
{
    if (!extensionListHas(extensions, "EGL_MESA_query_driver"))
        return {};
    using GetDriverName = const char* (*)(EGLDisplay);
    const auto getDriverName = reinterpret_cast<GetDriverName>(eglGetProcAddress("eglGetDisplayDriverName"));
    const char* name = getDriverName ? getDriverName(display) : nullptr;
    return name ? name : "";
}

// The DRM node of the display's EGLDevice, where EGL_EXT_device_query and EGL_EXT_device_drm
// are there (the first is a client extension, the second the device's).
std::string queryDrmDeviceFile(EGLDisplay display, std::string_view clientExtensions)
{
    if (!extensionListHas(clientExtensions, "EGL_EXT_device_query") &&
        !extensionListHas(clientExtensions, "EGL_EXT_device_base"))
        return {};
    const auto queryDisplay =
        reinterpret_cast<PFNEGLQUERYDISPLAYATTRIBEXTPROC>(eglGetProcAddress("eglQueryDisplayAttribEXT"));
    const auto queryDeviceString =
        reinterpret_cast<PFNEGLQUERYDEVICESTRINGEXTPROC>(eglGetProcAddress("eglQueryDeviceStringEXT"));
    EGLAttrib device = 0;
    if (!queryDisplay || !queryDeviceString || !queryDisplay(display, EGL_DEVICE_EXT, &device) || device == 0)
        return {};
    const auto handle = reinterpret_cast<EGLDeviceEXT>(device);
    const char* deviceExtensions = queryDeviceString(handle, EGL_EXTENSIONS);
    if (!deviceExtensions || !extensionListHas(deviceExtensions, "EGL_EXT_device_drm"))
        return {};
    const char* file = queryDeviceString(handle, EGL_DRM_DEVICE_FILE_EXT);
    return file ? file : "";
}

std::mutex sharedDisplayMutex;
std::weak_ptr<EglDisplay> sharedDisplay;

// The EGL devices in eglQueryDevicesEXT's order (none where EGL cannot enumerate them).
std::vector<EGLDeviceEXT> eglDevices()
{
    const char* clientExtensions = eglQueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS);
    const std::string_view client = clientExtensions ? clientExtensions : "";
    const auto queryDevices = reinterpret_cast<PFNEGLQUERYDEVICESEXTPROC>(eglGetProcAddress("eglQueryDevicesEXT"));
    if (!queryDevices ||
        !(extensionListHas(client, "EGL_EXT_device_enumeration") || extensionListHas(client, "EGL_EXT_device_base")))
        return {};
    EGLint count = 0;
    if (!queryDevices(0, nullptr, &count) || count <= 0)
        return {};
    std::vector<EGLDeviceEXT> devices(static_cast<size_t>(count));
    if (!queryDevices(count, devices.data(), &count))
        return {};
    devices.resize(size_t(std::max(count, 0)));
    return devices;
}

std::string deviceExtensionString(EGLDeviceEXT device)
{
    const auto queryString =
        reinterpret_cast<PFNEGLQUERYDEVICESTRINGEXTPROC>(eglGetProcAddress("eglQueryDeviceStringEXT"));
    const char* extensions = queryString ? queryString(device, EGL_EXTENSIONS) : nullptr;
    return extensions ? extensions : "";
}

} // namespace

std::shared_ptr<EglDisplay> EglDisplay::surfaceless()
{
    const std::lock_guard lock(sharedDisplayMutex);
    if (auto existing = sharedDisplay.lock())
        return existing;
    std::shared_ptr<EglDisplay> display;
    const char* forced = std::getenv("LUMAR_EGL_PLATFORM");
    const std::string_view choice = forced ? forced : "";
    if (choice == "surfaceless")
        display = initialise(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, "surfaceless");
    else if (choice == "device")
        display = device(0);
    else if (!choice.empty())
        throw RuntimeError("LUMAR_EGL_PLATFORM must be surfaceless or device, not \"" + std::string(choice) + "\"");
    else {
        const std::vector<std::string> devices = deviceExtensions();
        for (size_t i = 0; i < devices.size() && !display; ++i) {
            if (extensionListHas(devices[i], "EGL_MESA_device_software"))
                continue;
            try {
                // Mesa's devices are what its surfaceless platform draws with anyway: that
                // platform stays theirs, as tested on every board.
                auto candidate = device(int(i));
                const char* vendor = eglQueryString(candidate->handle(), EGL_VENDOR);
                const bool mesa = vendor && std::string_view(vendor).find("Mesa") != std::string_view::npos;
                if (!mesa && candidate->hasExtension("EGL_KHR_surfaceless_context"))
                    display = std::move(candidate);
            } catch (const RuntimeError& e) {
                LUMAR_LOG(Render, Warn) << "EGL device " << i << " left out: " << e.what();
            }
        }
        if (!display)
            display = initialise(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, "surfaceless");
    }
    sharedDisplay = display;
    return display;
}

std::vector<std::string> EglDisplay::deviceExtensions()
{
    std::vector<std::string> extensions;
    for (const EGLDeviceEXT device : eglDevices())
        extensions.push_back(deviceExtensionString(device));
    return extensions;
}

std::shared_ptr<EglDisplay> EglDisplay::device(int index)
{
    const std::vector<EGLDeviceEXT> devices = eglDevices();
    if (index < 0 || size_t(index) >= devices.size())
        throw RuntimeError("no EGL device " + std::to_string(index) + " (EGL lists " + std::to_string(devices.size()) +
                           ")");
    return initialise(EGL_PLATFORM_DEVICE_EXT, devices[size_t(index)], "device");
}

std::shared_ptr<EglDisplay> EglDisplay::gbm(void* gbmDevice)
{
    return initialise(EGL_PLATFORM_GBM_KHR, gbmDevice, "GBM");
}

std::shared_ptr<EglDisplay> EglDisplay::x11(void* xlibDisplay)
{
    return initialise(EGL_PLATFORM_X11_KHR, xlibDisplay, "X11");
}

std::shared_ptr<EglDisplay> EglDisplay::wayland(void* wlDisplay)
{
    return initialise(EGL_PLATFORM_WAYLAND_KHR, wlDisplay, "Wayland");
}

std::shared_ptr<EglDisplay> EglDisplay::initialise(EGLenum platform, void* nativeDisplay, const char* what)
{
    const char* clientExtensions = eglQueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS);
    const std::string_view client = clientExtensions ? clientExtensions : "";
    const auto getPlatformDisplay =
        reinterpret_cast<PFNEGLGETPLATFORMDISPLAYEXTPROC>(eglGetProcAddress("eglGetPlatformDisplayEXT"));
    const bool platformKnown =
        platform == EGL_PLATFORM_SURFACELESS_MESA ? extensionListHas(client, "EGL_MESA_platform_surfaceless")
        : platform == EGL_PLATFORM_DEVICE_EXT     ? extensionListHas(client, "EGL_EXT_platform_device")
        : platform == EGL_PLATFORM_X11_KHR
            ? extensionListHas(client, "EGL_KHR_platform_x11") || extensionListHas(client, "EGL_EXT_platform_x11")
        : platform == EGL_PLATFORM_WAYLAND_KHR
            ? extensionListHas(client, "EGL_KHR_platform_wayland") ||
                  extensionListHas(client, "EGL_EXT_platform_wayland")
            : extensionListHas(client, "EGL_KHR_platform_gbm") || extensionListHas(client, "EGL_MESA_platform_gbm");
    const std::string missing =
        std::string("no EGL display for the ") + what + " platform (is Mesa's libegl-mesa0 installed?)";
    if (!extensionListHas(client, "EGL_EXT_platform_base") || !platformKnown || !getPlatformDisplay)
        throw RuntimeError(missing);

    std::shared_ptr<EglDisplay> display(new EglDisplay());
    display->display_ = getPlatformDisplay(platform, nativeDisplay, nullptr);
    if (display->display_ == EGL_NO_DISPLAY)
        throw RuntimeError(missing);
    EGLint major = 0, minor = 0;
    if (!eglInitialize(display->display_, &major, &minor)) {
        display->display_ = EGL_NO_DISPLAY;
        throw RuntimeError(std::string("cannot initialise the ") + what +
                           " EGL display: " + eglErrorName(eglGetError()));
    }
    display->major_ = major;
    display->minor_ = minor;
    const char* extensions = eglQueryString(display->display_, EGL_EXTENSIONS);
    display->extensions_ = extensions ? extensions : "";
    display->driverName_ = queryDriverName(display->display_, display->extensions_);
    display->drmDeviceFile_ = queryDrmDeviceFile(display->display_, client);
    display->platformName_ = what;
    return display;
}

EglDisplay::EglDisplay(EglDisplay&& other) noexcept
    : display_(std::exchange(other.display_, EGL_NO_DISPLAY)), windowConfig_(other.windowConfig_), major_(other.major_),
      minor_(other.minor_), extensions_(std::move(other.extensions_)), driverName_(std::move(other.driverName_)),
      drmDeviceFile_(std::move(other.drmDeviceFile_)), platformName_(std::move(other.platformName_))
{
}

EglDisplay& EglDisplay::operator=(EglDisplay&& other) noexcept
{
    if (this != &other) {
        terminate();
        display_ = std::exchange(other.display_, EGL_NO_DISPLAY);
        windowConfig_ = other.windowConfig_;
        major_ = other.major_;
        minor_ = other.minor_;
        extensions_ = std::move(other.extensions_);
        driverName_ = std::move(other.driverName_);
        drmDeviceFile_ = std::move(other.drmDeviceFile_);
        platformName_ = std::move(other.platformName_);
    }
    return *this;
}

EglDisplay::~EglDisplay()
{
    terminate();
}

void EglDisplay::terminate()
{
    if (display_ != EGL_NO_DISPLAY)
        eglTerminate(display_);
    display_ = EGL_NO_DISPLAY;
}

bool EglDisplay::hasExtension(std::string_view name) const
{
    return extensionListHas(extensions_, name);
}

EglContext::EglContext(std::shared_ptr<EglDisplay> display) : display_(std::move(display))
{
    const EGLDisplay dpy = display_->handle();
    if (!display_->hasExtension("EGL_KHR_surfaceless_context"))
        throw RuntimeError("no OpenGL ES 3 context: the EGL display lacks EGL_KHR_surfaceless_context");
    if (!eglBindAPI(EGL_OPENGL_ES_API))
        throw RuntimeError("no OpenGL ES 3 context: eglBindAPI(EGL_OPENGL_ES_API) failed: " +
                           eglErrorName(eglGetError()));

    // A context needs no config where EGL_KHR_no_config_context exists; otherwise the window
    // config where there is a window to draw to, else any ES 3 config (nothing is drawn to
    // an EGL surface then).
    EGLConfig config = EGL_NO_CONFIG_KHR;
    if (!display_->hasExtension("EGL_KHR_no_config_context") && display_->windowConfig()) {
        config = display_->windowConfig();
    } else if (!display_->hasExtension("EGL_KHR_no_config_context")) {
        const EGLint configAttributes[] = {EGL_RENDERABLE_TYPE, EGL_OPENGL_ES3_BIT, EGL_SURFACE_TYPE, 0, EGL_NONE};
        EGLint count = 0;
        if (!eglChooseConfig(dpy, configAttributes, &config, 1, &count) || count < 1)
            throw RuntimeError("no OpenGL ES 3 context: no EGL config with EGL_OPENGL_ES3_BIT");
    }
    const EGLint contextAttributes[] = {EGL_CONTEXT_MAJOR_VERSION, 3, EGL_CONTEXT_MINOR_VERSION, 0, EGL_NONE};
    context_ = eglCreateContext(dpy, config, EGL_NO_CONTEXT, contextAttributes);
    if (context_ == EGL_NO_CONTEXT)
        throw RuntimeError("no OpenGL ES 3 context: eglCreateContext failed: " + eglErrorName(eglGetError()));
    if (!eglMakeCurrent(dpy, EGL_NO_SURFACE, EGL_NO_SURFACE, context_)) {
        const std::string error = eglErrorName(eglGetError());
        destroy();
        throw RuntimeError("no OpenGL ES 3 context: eglMakeCurrent without a surface failed: " + error);
    }
}

EglContext::EglContext(EglContext&& other) noexcept
    : display_(std::move(other.display_)), context_(std::exchange(other.context_, EGL_NO_CONTEXT))
{
}

EglContext& EglContext::operator=(EglContext&& other) noexcept
{
    if (this != &other) {
        destroy();
        display_ = std::move(other.display_);
        context_ = std::exchange(other.context_, EGL_NO_CONTEXT);
    }
    return *this;
}

EglContext::~EglContext()
{
    destroy();
}

void EglContext::destroy()
{
    if (context_ == EGL_NO_CONTEXT)
        return;
    if (eglGetCurrentContext() == context_)
        eglMakeCurrent(display_->handle(), EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
    eglDestroyContext(display_->handle(), context_);
    context_ = EGL_NO_CONTEXT;
}

void EglContext::makeCurrent(EGLSurface surface) const
{
    if (eglGetCurrentContext() == context_ && eglGetCurrentSurface(EGL_DRAW) == surface)
        return;
    if (!eglMakeCurrent(display_->handle(), surface, surface, context_))
        throw RuntimeError("cannot make the OpenGL ES context current with its window: " + eglErrorName(eglGetError()));
}

void EglContext::makeCurrent() const
{
    if (eglGetCurrentContext() == context_)
        return;
    if (!eglMakeCurrent(display_->handle(), EGL_NO_SURFACE, EGL_NO_SURFACE, context_))
        throw RuntimeError("cannot make the OpenGL ES context current: " + eglErrorName(eglGetError()));
}

EGLConfig chooseWindowConfig(EGLDisplay display, const std::function<int(EGLint nativeVisualId)>& rank,
                             const char* where, const char* rejectedWhy)
{
    const EGLint attributes[] = {EGL_SURFACE_TYPE,
                                 EGL_WINDOW_BIT,
                                 EGL_RENDERABLE_TYPE,
                                 EGL_OPENGL_ES3_BIT,
                                 EGL_RED_SIZE,
                                 8,
                                 EGL_GREEN_SIZE,
                                 8,
                                 EGL_BLUE_SIZE,
                                 8,
                                 EGL_NONE};
    EGLint count = 0;
    if (!eglChooseConfig(display, attributes, nullptr, 0, &count) || count < 1)
        throw RuntimeError(std::string("no EGL window config with OpenGL ES 3 and 8-bit colour on the ") + where +
                           " display");
    std::vector<EGLConfig> configs(static_cast<size_t>(count));
    if (!eglChooseConfig(display, attributes, configs.data(), count, &count))
        throw RuntimeError(std::string("cannot list the EGL window configs on the ") + where +
                           " display: " + eglErrorName(eglGetError()));
    EGLConfig chosen = nullptr;
    int best = -1;
    for (EGLint i = 0; i < count; ++i) {
        EGLint visual = 0;
        if (!eglGetConfigAttrib(display, configs[size_t(i)], EGL_NATIVE_VISUAL_ID, &visual))
            continue;
        const int score = rank(visual);
        if (score > best) {
            best = score;
            chosen = configs[size_t(i)];
        }
    }
    if (!chosen)
        throw RuntimeError(rejectedWhy);
    return chosen;
}

EglWindowSurface::EglWindowSurface(std::shared_ptr<EglDisplay> display, void* gbmSurface, uint32_t gbmFormat)
    : display_(std::move(display))
{
    const EGLDisplay dpy = display_->handle();
    // GBM surfaces take the config whose native visual id is their DRM format.
    const EGLConfig chosen = chooseWindowConfig(
        dpy, [gbmFormat](EGLint visual) { return uint32_t(visual) == gbmFormat ? 0 : -1; }, "GBM",
        "no EGL window config for the scan-out format");
    const auto createSurface = reinterpret_cast<PFNEGLCREATEPLATFORMWINDOWSURFACEEXTPROC>(
        eglGetProcAddress("eglCreatePlatformWindowSurfaceEXT"));
    if (!createSurface)
        throw RuntimeError("EGL lacks eglCreatePlatformWindowSurfaceEXT");
    surface_ = createSurface(dpy, chosen, gbmSurface, nullptr);
    if (surface_ == EGL_NO_SURFACE)
        throw RuntimeError("cannot create the EGL window surface on GBM: " + eglErrorName(eglGetError()));
    display_->setWindowConfig(chosen);
}

EglWindowSurface::EglWindowSurface(EglWindowSurface&& other) noexcept
    : display_(std::move(other.display_)), surface_(std::exchange(other.surface_, EGL_NO_SURFACE))
{
}

EglWindowSurface& EglWindowSurface::operator=(EglWindowSurface&& other) noexcept
{
    if (this != &other) {
        destroy();
        display_ = std::move(other.display_);
        surface_ = std::exchange(other.surface_, EGL_NO_SURFACE);
    }
    return *this;
}

EglWindowSurface::~EglWindowSurface()
{
    destroy();
}

void EglWindowSurface::destroy()
{
    if (surface_ == EGL_NO_SURFACE)
        return;
    // A surface still bound is only destroyed once it is released: release it now.
    if (eglGetCurrentSurface(EGL_DRAW) == surface_)
        eglMakeCurrent(display_->handle(), EGL_NO_SURFACE, EGL_NO_SURFACE, eglGetCurrentContext());
    eglDestroySurface(display_->handle(), surface_);
    surface_ = EGL_NO_SURFACE;
}

void EglWindowSurface::swapBuffers() const
{
    if (!eglSwapBuffers(display_->handle(), surface_))
        throw RuntimeError("eglSwapBuffers failed: " + eglErrorName(eglGetError()));
}

} // namespace lumar
