#include "gl/x11_viewer.h"

#include <X11/Xlib.h>
#include <X11/Xutil.h>

namespace lumar::test {
namespace {

Display* asDisplay(void* display)
{
    return static_cast<Display*>(display);
}

int shiftOf(unsigned long mask)
{
    return mask ? __builtin_ctzl(mask) : 0;
}

// Xlib's default handler ends the process on any protocol error; a grab of a window not
// viewable yet (found by its name between its creation and its mapping) is one.
extern "C" int ignoreError(Display*, XErrorEvent*)
{
    return 0;
}

// The window's _NET_WM_NAME (UTF-8), what clients that set no WM_NAME (weston's X11 backend)
// are titled by.
std::string netWmName(Display* display, Window window)
{
    Atom type = 0;
    int format = 0;
    unsigned long items = 0, after = 0;
    unsigned char* data = nullptr;
    std::string title;
    if (XGetWindowProperty(display, window, XInternAtom(display, "_NET_WM_NAME", False), 0, 1024, False,
                           XInternAtom(display, "UTF8_STRING", False), &type, &format, &items, &after,
                           &data) == Success &&
        data) {
        if (format == 8)
            title.assign(reinterpret_cast<const char*>(data), items);
        XFree(data);
    }
    return title;
}

} // namespace

X11Viewer::X11Viewer(const std::string& displayName) : display_(XOpenDisplay(displayName.c_str())) {}

X11Viewer::~X11Viewer()
{
    close();
}

void X11Viewer::close()
{
    if (display_)
        XCloseDisplay(asDisplay(display_));
    display_ = nullptr;
}

unsigned long X11Viewer::findWindow(const std::string& name) const
{
    Display* display = asDisplay(display_);
    Window root = 0, parent = 0, *children = nullptr;
    unsigned count = 0;
    Window found = 0;
    if (!XQueryTree(display, DefaultRootWindow(display), &root, &parent, &children, &count))
        return 0;
    for (unsigned i = 0; i < count && !found; ++i) {
        char* title = nullptr;
        if (XFetchName(display, children[i], &title) && title) {
            if (name == title)
                found = children[i];
            XFree(title);
        } else if (name == netWmName(display, children[i])) {
            found = children[i];
        }
    }
    if (children)
        XFree(children);
    return found;
}

std::vector<uint8_t> X11Viewer::grab(unsigned long window, int width, int height) const
{
    std::vector<uint8_t> rgb;
    Display* display = asDisplay(display_);
    XSync(display, False);
    const auto previous = XSetErrorHandler(ignoreError);
    XImage* image = XGetImage(display, Window(window), 0, 0, unsigned(width), unsigned(height), AllPlanes, ZPixmap);
    XSync(display, False);
    XSetErrorHandler(previous);
    if (!image)
        return rgb;
    rgb.reserve(size_t(width) * size_t(height) * 3);
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x) {
            const unsigned long pixel = XGetPixel(image, x, y);
            rgb.push_back(uint8_t((pixel & image->red_mask) >> shiftOf(image->red_mask)));
            rgb.push_back(uint8_t((pixel & image->green_mask) >> shiftOf(image->green_mask)));
            rgb.push_back(uint8_t((pixel & image->blue_mask) >> shiftOf(image->blue_mask)));
        }
    XDestroyImage(image);
    return rgb;
}

void X11Viewer::requestClose(unsigned long window) const
{
    Display* display = asDisplay(display_);
    XEvent event{};
    event.xclient.type = ClientMessage;
    event.xclient.window = Window(window);
    event.xclient.message_type = XInternAtom(display, "WM_PROTOCOLS", False);
    event.xclient.format = 32;
    event.xclient.data.l[0] = long(XInternAtom(display, "WM_DELETE_WINDOW", False));
    event.xclient.data.l[1] = CurrentTime;
    XSendEvent(display, Window(window), False, NoEventMask, &event);
    XSync(display, False);
}

void X11Viewer::resize(unsigned long window, int width, int height) const
{
    XResizeWindow(asDisplay(display_), Window(window), unsigned(width), unsigned(height));
    XSync(asDisplay(display_), False);
}

void X11Viewer::typeKey(unsigned long window, char c) const
{
    Display* display = asDisplay(display_);
    XEvent event{};
    event.xkey.display = display;
    event.xkey.window = Window(window);
    event.xkey.root = DefaultRootWindow(display);
    event.xkey.time = CurrentTime;
    event.xkey.same_screen = True;
    event.xkey.keycode = XKeysymToKeycode(display, KeySym(static_cast<unsigned char>(c)));
    // Pressed and released: a compositor on X (weston's X11 backend) ignores a second press of
    // a key it believes still held.
    event.xkey.type = KeyPress;
    XSendEvent(display, Window(window), True, KeyPressMask, &event);
    event.xkey.type = KeyRelease;
    XSendEvent(display, Window(window), True, KeyReleaseMask, &event);
    XSync(display, False);
}

} // namespace lumar::test
