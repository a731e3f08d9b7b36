#include "gles_renderer/window/x11_window.h"

#include <algorithm>
#include <chrono>
#include <thread>

#include <EGL/eglext.h>
#include <X11/Xlib.h>
#include <X11/Xutil.h>
#include <X11/extensions/XShm.h>
#include <poll.h>
#include <sys/ipc.h>
#include <sys/shm.h>
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

// The frame shown through MIT-SHM: an XImage whose pixels live in a System V shared segment
// the X server has attached too.
struct X11Window::SharedImage {
    Display* display = nullptr;
    XImage* image = nullptr;
    XShmSegmentInfo segment{};
    bool attached = false;

    SharedImage() { segment.shmid = -1; }
    SharedImage(const SharedImage&) = delete;
    SharedImage& operator=(const SharedImage&) = delete;
    // `serverAlive`: false after the connection broke (no more requests then).
    void release(bool serverAlive)
    {
        if (attached && serverAlive) {
            XShmDetach(display, &segment);
            XSync(display, False);
        }
        attached = false;
        if (image) {
            image->data = nullptr; // the segment's, not malloc's: XDestroyImage must not free it
            XDestroyImage(image);
            image = nullptr;
        }
        if (segment.shmaddr && segment.shmaddr != reinterpret_cast<char*>(-1))
            shmdt(segment.shmaddr);
        segment.shmaddr = nullptr;
    }
    ~SharedImage() { release(false); }
};

namespace {

bool gSharedMemoryRefused = false;

extern "C" int trapSharedMemoryError(Display*, XErrorEvent*)
{
    gSharedMemoryRefused = true;
    return 0;
}

// A `width` x `height` image in a shared segment the server has attached, or nullptr (with
// `why`) where MIT-SHM is missing, refused (a server on another machine) or the visual's
// pixels are not 32-bit B, G, R, X in memory.
std::unique_ptr<X11Window::SharedImage> makeSharedImage(Display* display, Visual* visual, int depth, int width,
                                                        int height, std::string& why)
{
    if (!XShmQueryExtension(display)) {
        why = "the X server has no MIT-SHM";
        return nullptr;
    }
    auto shared = std::make_unique<X11Window::SharedImage>();
    shared->display = display;
    shared->image = XShmCreateImage(display, visual, unsigned(depth), ZPixmap, nullptr, &shared->segment,
                                    unsigned(width), unsigned(height));
    if (!shared->image) {
        why = "XShmCreateImage failed";
        return nullptr;
    }
    const XImage& image = *shared->image;
    if (image.bits_per_pixel != 32 || image.byte_order != LSBFirst || image.red_mask != 0xff0000 ||
        image.green_mask != 0xff00 || image.blue_mask != 0xff) {
        why = "the window's visual is not 32-bit BGRX";
        shared->release(true);
        return nullptr;
    }
    shared->segment.shmid = shmget(IPC_PRIVATE, size_t(image.bytes_per_line) * size_t(height), IPC_CREAT | 0600);
    if (shared->segment.shmid < 0) {
        why = "shmget failed";
        shared->release(true);
        return nullptr;
    }
    shared->segment.shmaddr = static_cast<char*>(shmat(shared->segment.shmid, nullptr, 0));
    shared->image->data = shared->segment.shmaddr;
    shared->segment.readOnly = True;
    bool attached = false;
    if (shared->segment.shmaddr != reinterpret_cast<char*>(-1)) {
        gSharedMemoryRefused = false;
        XSync(display, False);
        const auto previous = XSetErrorHandler(trapSharedMemoryError);
        attached = XShmAttach(display, &shared->segment) && (XSync(display, False), !gSharedMemoryRefused);
        XSetErrorHandler(previous);
    }
    // Removed now: the segment goes when both sides have detached, even if lumar dies.
    shmctl(shared->segment.shmid, IPC_RMID, nullptr);
    if (!attached) {
        why = "the X server refused the shared segment (a server on another machine?)";
        shared->release(true);
        return nullptr;
    }
    shared->attached = true;
    return shared;
}

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

// The X visual behind an EGL config's native visual id: depth 0 when the server has none.
XVisualInfo visualOf(Display* x, EGLint visualId)
{
    XVisualInfo visual{};
    if (visualId == 0)
        return visual;
    XVisualInfo wanted{};
    wanted.visualid = VisualID(visualId);
    int found = 0;
    if (XVisualInfo* info = XGetVisualInfo(x, VisualIDMask, &wanted, &found)) {
        visual = *info;
        XFree(info);
    }
    return visual;
}

// An ES 3 window config whose X visual has 24 bits of depth (a 32-bit ARGB visual would make a
// compositor blend the window with what lies behind it), else any with an X visual.
EGLConfig chooseConfig(EGLDisplay egl, Display* x, XVisualInfo& visual)
{
    const EGLConfig config = chooseWindowConfig(
        egl,
        [x](EGLint id) {
            const int depth = visualOf(x, id).depth;
            return depth == 24 ? 1 : depth > 0 ? 0 : -1;
        },
        "X11", "no EGL window config with an X visual on the X11 display");
    EGLint id = 0;
    eglGetConfigAttrib(egl, config, EGL_NATIVE_VISUAL_ID, &id);
    visual = visualOf(x, id);
    return config;
}

} // namespace

std::unique_ptr<X11Window> X11Window::open(const std::string& displayName, const std::string& title, int width,
                                           int height, std::string& why, X11Presentation presentation)
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
    attributes.event_mask = StructureNotifyMask | KeyPressMask;
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

    const std::string& driver = window->eglDisplay_->driverName();
    const bool software = driver == "swrast" || driver == "kms_swrast";
    if (presentation == X11Presentation::SharedMemory || (presentation == X11Presentation::Auto && software)) {
        window->visual_ = visual.visual;
        window->visualDepth_ = visual.depth;
        std::string refused;
        window->image_ =
            makeSharedImage(x.display, visual.visual, visual.depth, window->width_, window->height_, refused);
        if (window->image_) {
            window->gc_ = XCreateGC(x.display, window->window_, 0, nullptr);
            window->sharedMemory_ = true;
        } else {
            LUMAR_LOG(Output, Info) << "preview window: no MIT-SHM presentation (" << refused
                                    << "); frames go through EGL's window surface";
        }
    }
    window->eglDisplay_->setWindowConfig(config);
    if (window->sharedMemory_) {
        LUMAR_LOG(Output, Info) << "preview window " << width << "x" << height << " on X display "
                                << DisplayString(x.display) << " (EGL " << driver << ", shown through MIT-SHM)";
        return window;
    }

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
    const bool alive = x_ && x_->alive();
    if (image_)
        image_->release(alive);
    if (alive && gc_)
        XFreeGC(x_->display, static_cast<GC>(gc_));
    if (alive) {
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
        } else if (event.type == KeyPress) {
            char typed[8] = {};
            KeySym symbol = 0;
            const int length = XLookupString(&event.xkey, typed, int(sizeof typed), &symbol, nullptr);
            typed_.append(typed, size_t(std::max(0, length)));
        }
    }
    if (x_->lost)
        throw RuntimeError(std::string("the X display closed under the preview window"));
}

std::optional<WindowTarget::CpuPixels> X11Window::cpuPixels()
{
    if (!sharedMemory_)
        return std::nullopt;
    if (!x_->alive())
        throw RuntimeError("the X display closed under the preview window");
    if (image_->image->width != width_ || image_->image->height != height_) {
        // Resized: a segment of the new size.
        image_->release(x_->alive());
        std::string why;
        image_ = makeSharedImage(x_->display, static_cast<Visual*>(visual_), visualDepth_, width_, height_, why);
        if (!image_)
            throw RuntimeError("cannot resize the preview window's shared image: " + why);
    }
    return CpuPixels{reinterpret_cast<uint8_t*>(image_->image->data), image_->image->bytes_per_line};
}

void X11Window::showSwapped()
{
    ++framesShown_;
    if (sharedMemory_ && x_->alive())
        XShmPutImage(x_->display, window_, static_cast<GC>(gc_), image_->image, 0, 0, 0, 0,
                     unsigned(image_->image->width), unsigned(image_->image->height), False);
    // One round trip a frame: the X server has drawn this frame before the next is rendered,
    // so a slow server slows the loop down instead of queueing frames without bound.
    if (x_->alive())
        XSync(x_->display, False);
    pollEvents();
}

} // namespace lumar
