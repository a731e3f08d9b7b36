#include "gles_renderer/window/x11_window.h"

#include <chrono>
#include <thread>
#include <vector>

#include <EGL/eglext.h>
#include <X11/Xlib.h>
#include <X11/Xutil.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include "core/error.h"
#include "core/log.h"

namespace lumar {

struct X11Window::XConnection {
    Display* display = nullptr;
    bool lost = false; // the connection broke: every X call is a no-op from here on

    // Whether the connection still stands, asked of its socket before Xlib is: after an I/O
    // error that Mesa's own use of the connection met first, Xlib's next request can crash
    // (libX11 1.8: "request N would exceed buffer size", then a null request is written to).
    bool alive()
    {
        if (lost || !display)
            return false;
        pollfd socket{ConnectionNumber(display), POLLIN, 0};
        if (poll(&socket, 1, 0) > 0) {
            char byte = 0;
            if ((socket.revents & (POLLHUP | POLLERR | POLLNVAL)) != 0 ||
                recv(socket.fd, &byte, 1, MSG_PEEK | MSG_DONTWAIT) == 0)
                lost = true;
        }
        return !lost;
    }

    XConnection() = default;
    XConnection(const XConnection&) = delete;
    XConnection& operator=(const XConnection&) = delete;
    ~XConnection()
    {
        if (display)
            XCloseDisplay(display);
    }
};

namespace {

// Xlib's default handlers print several lines and exit(1) on a broken connection or any
// protocol error; lumar says it in one line. libX11 >= 1.7 lets the exit handler return, but
// 1.8 (Debian 12) then crashes in the request that met the error ("request N would exceed
// buffer size", a write through a null request), so a loss Xlib meets inside a call ends the
// process here, with the one line and exit status 1 (RuntimeError's). Losses seen between
// calls (XConnection::alive) are thrown as RuntimeError as usual.
extern "C" int quietIoError(Display*)
{
    return 0;
}

extern "C" void markConnectionLost(Display*, void* connection)
{
    *static_cast<bool*>(connection) = true;
    static const char kLine[] = "lumar: the X display closed under the preview window\n";
    [[maybe_unused]] const ssize_t written = ::write(STDERR_FILENO, kLine, sizeof kLine - 1);
    ::_exit(1);
}

extern "C" int logProtocolError(Display* display, XErrorEvent* error)
{
    char text[160] = {};
    XGetErrorText(display, error->error_code, text, sizeof text);
    LUMAR_LOG(Output, Warn) << "X11 error on the preview window: " << text << " (request " << int(error->request_code)
                            << ")";
    return 0;
}

// An ES 3 window config whose X visual has 24 bits of depth (a 32-bit ARGB visual would make a
// compositor blend the window with what lies behind it).
EGLConfig chooseConfig(EGLDisplay egl, Display* x, XVisualInfo& visual)
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
    if (!eglChooseConfig(egl, attributes, nullptr, 0, &count) || count < 1)
        throw RuntimeError("no EGL window config with OpenGL ES 3 and 8-bit colour on the X11 display");
    std::vector<EGLConfig> configs(static_cast<size_t>(count));
    eglChooseConfig(egl, attributes, configs.data(), count, &count);
    EGLConfig fallback = nullptr;
    for (EGLint i = 0; i < count; ++i) {
        EGLint id = 0;
        if (!eglGetConfigAttrib(egl, configs[size_t(i)], EGL_NATIVE_VISUAL_ID, &id) || id == 0)
            continue;
        XVisualInfo wanted{};
        wanted.visualid = VisualID(id);
        int found = 0;
        XVisualInfo* info = XGetVisualInfo(x, VisualIDMask, &wanted, &found);
        if (!info)
            continue;
        const bool opaque = info->depth == 24;
        if (opaque || !fallback) {
            visual = *info;
            fallback = configs[size_t(i)];
        }
        XFree(info);
        if (opaque)
            return configs[size_t(i)];
    }
    if (!fallback)
        throw RuntimeError("no EGL window config with an X visual on the X11 display");
    return fallback;
}

} // namespace

std::unique_ptr<X11Window> X11Window::open(const std::string& displayName, const std::string& title, int width,
                                           int height, std::string& why)
{
    auto window = std::unique_ptr<X11Window>(new X11Window());
    window->x_ = std::make_unique<XConnection>();
    XConnection& x = *window->x_;
    x.display = XOpenDisplay(displayName.empty() ? nullptr : displayName.c_str());
    if (!x.display) {
        const char* fromEnvironment = std::getenv("DISPLAY");
        const std::string name = displayName.empty() ? (fromEnvironment ? fromEnvironment : "") : displayName;
        why = name.empty() ? "DISPLAY is not set" : "cannot connect to X display '" + name + "'";
        return nullptr;
    }
    XSetIOErrorHandler(quietIoError);
    XSetIOErrorExitHandler(x.display, markConnectionLost, &x.lost);
    XSetErrorHandler(logProtocolError);

    window->eglDisplay_ = EglDisplay::x11(x.display);
    const EGLDisplay egl = window->eglDisplay_->handle();
    XVisualInfo visual{};
    const EGLConfig config = chooseConfig(egl, x.display, visual);

    const Window root = RootWindow(x.display, visual.screen);
    XSetWindowAttributes attributes{};
    window->colormap_ = XCreateColormap(x.display, root, visual.visual, AllocNone);
    attributes.colormap = window->colormap_;
    attributes.background_pixel = BlackPixel(x.display, visual.screen);
    attributes.border_pixel = 0;
    attributes.event_mask = StructureNotifyMask;
    window->window_ =
        XCreateWindow(x.display, root, 0, 0, unsigned(width), unsigned(height), 0, visual.depth, InputOutput,
                      visual.visual, CWColormap | CWBackPixel | CWBorderPixel | CWEventMask, &attributes);
    window->width_ = width;
    window->height_ = height;
    XStoreName(x.display, window->window_, title.c_str());
    XClassHint classHint{const_cast<char*>("lumar"), const_cast<char*>("lumar")};
    XSetClassHint(x.display, window->window_, &classHint);
    window->setAspectHint(width, height);
    Atom deleteMessage = XInternAtom(x.display, "WM_DELETE_WINDOW", False);
    window->deleteMessage_ = deleteMessage;
    XSetWMProtocols(x.display, window->window_, &deleteMessage, 1);
    XMapWindow(x.display, window->window_);

    // Frames drawn before the window is mapped would be lost: wait for it (a window manager
    // answers within milliseconds; after 2 s the frames start anyway).
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(2);
    for (bool mapped = false; !mapped && !x.lost && std::chrono::steady_clock::now() < deadline;) {
        while (!mapped && XPending(x.display)) {
            XEvent event;
            XNextEvent(x.display, &event);
            mapped = event.type == MapNotify;
            if (event.type == ConfigureNotify) {
                window->width_ = event.xconfigure.width;
                window->height_ = event.xconfigure.height;
            }
        }
        if (!mapped)
            std::this_thread::sleep_for(std::chrono::milliseconds(2));
    }
    if (x.lost)
        throw RuntimeError("the X display closed while opening the preview window");

    const auto createSurface = reinterpret_cast<PFNEGLCREATEPLATFORMWINDOWSURFACEEXTPROC>(
        eglGetProcAddress("eglCreatePlatformWindowSurfaceEXT"));
    if (!createSurface)
        throw RuntimeError("EGL lacks eglCreatePlatformWindowSurfaceEXT");
    Window native = window->window_;
    window->surface_ = createSurface(egl, config, &native, nullptr);
    if (window->surface_ == EGL_NO_SURFACE)
        throw RuntimeError("cannot create an EGL window surface on the X11 window (EGL error " +
                           std::to_string(eglGetError()) + ")");
    window->eglDisplay_->setWindowConfig(config);
    LUMAR_LOG(Output, Info) << "preview window " << width << "x" << height << " on X display "
                            << DisplayString(x.display) << " (EGL " << window->eglDisplay_->driverName() << ")";
    return window;
}

X11Window::~X11Window()
{
    if (surface_ != EGL_NO_SURFACE) {
        // A surface still bound is only destroyed once released.
        if (eglGetCurrentSurface(EGL_DRAW) == surface_)
            eglMakeCurrent(eglDisplay_->handle(), EGL_NO_SURFACE, EGL_NO_SURFACE, eglGetCurrentContext());
        eglDestroySurface(eglDisplay_->handle(), surface_);
    }
    // EGL lets go of the X connection before it closes.
    eglDisplay_.reset();
    if (x_ && x_->alive()) {
        if (window_)
            XDestroyWindow(x_->display, window_);
        if (colormap_)
            XFreeColormap(x_->display, colormap_);
    }
}

void X11Window::setAspectHint(int width, int height)
{
    // The window manager keeps the frame's aspect while the user resizes; present() fits the
    // frame with black bars wherever the window ends up otherwise (e.g. maximised).
    XSizeHints* hints = XAllocSizeHints();
    hints->flags = PAspect;
    hints->min_aspect.x = hints->max_aspect.x = width;
    hints->min_aspect.y = hints->max_aspect.y = height;
    XSetWMNormalHints(x_->display, window_, hints);
    XFree(hints);
}

void X11Window::fitFrame(int width, int height)
{
    if (!x_->alive() || width <= 0 || height <= 0)
        return;
    setAspectHint(width, height);
    XResizeWindow(x_->display, window_, unsigned(width), unsigned(height));
    // The new size arrives with its ConfigureNotify: wait for it, so the next frame fills
    // the window instead of landing in the old size's corner.
    XSync(x_->display, False);
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(1);
    while ((width_ != width || height_ != height) && std::chrono::steady_clock::now() < deadline) {
        pollEvents();
        if (width_ != width || height_ != height)
            std::this_thread::sleep_for(std::chrono::milliseconds(2));
    }
}

void X11Window::pollEvents()
{
    Display* display = x_->display;
    while (x_->alive() && XPending(display)) {
        XEvent event;
        XNextEvent(display, &event);
        if (event.type == ConfigureNotify) {
            width_ = event.xconfigure.width;
            height_ = event.xconfigure.height;
        } else if (event.type == ClientMessage && Atom(event.xclient.data.l[0]) == Atom(deleteMessage_)) {
            closeRequested_ = true;
        } else if (event.type == DestroyNotify) {
            closeRequested_ = true;
        }
    }
    if (x_->lost)
        throw RuntimeError(std::string("the X display closed under the preview window"));
}

void X11Window::showSwapped()
{
    ++framesShown_;
    // One round trip a frame: the X server has drawn this frame before the next is rendered,
    // so a slow server slows the loop down instead of queueing frames without bound.
    if (x_->alive())
        XSync(x_->display, False);
    pollEvents();
}

} // namespace lumar
