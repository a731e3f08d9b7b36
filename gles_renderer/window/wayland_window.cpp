#include "gles_renderer/window/wayland_window.h"

#include <algorithm>
#include <cerrno>
#include <climits>
#include <cstdlib>
#include <cstring>
#include <vector>

#include <EGL/eglext.h>
#include <poll.h>
#include <sys/mman.h>
#include <unistd.h>
#include <wayland-client.h>
#include <wayland-egl.h>
#include <xkbcommon/xkbcommon.h>

#include "core/error.h"
#include "core/log.h"
#include "xdg-shell-client-protocol.h"

namespace lumar {
namespace {

// A frame's worth of shared memory the compositor reads: a memfd mapped here, one wl_buffer.
struct ShmBuffer {
    wl_buffer* buffer = nullptr;
    uint8_t* data = nullptr;
    size_t size = 0;
    int width = 0, height = 0, stride = 0;
    bool busy = false; // attached and not released yet: not written to
    uint64_t* released = nullptr;

    ShmBuffer() = default;
    ShmBuffer(const ShmBuffer&) = delete;
    ShmBuffer& operator=(const ShmBuffer&) = delete;
    ~ShmBuffer()
    {
        if (buffer)
            wl_buffer_destroy(buffer);
        if (data)
            munmap(data, size);
    }
};

const wl_buffer_listener kBufferListener = {
    .release =
        [](void* data, wl_buffer*) {
            auto* shm = static_cast<ShmBuffer*>(data);
            shm->busy = false;
            ++*shm->released;
        },
};

std::unique_ptr<ShmBuffer> makeShmBuffer(wl_shm* shm, int width, int height, uint64_t* released)
{
    auto buffer = std::make_unique<ShmBuffer>();
    buffer->width = width;
    buffer->height = height;
    buffer->stride = width * 4;
    buffer->size = size_t(buffer->stride) * size_t(height);
    buffer->released = released;
    const int fd = memfd_create("lumar-preview", MFD_CLOEXEC);
    if (fd < 0)
        throw RuntimeError(std::string("memfd_create for the preview window failed: ") + std::strerror(errno));
    if (ftruncate(fd, off_t(buffer->size)) != 0) {
        const int error = errno;
        close(fd);
        throw RuntimeError(std::string("cannot size the preview window's shared memory: ") + std::strerror(error));
    }
    void* data = mmap(nullptr, buffer->size, PROT_READ | PROT_WRITE, MAP_SHARED, fd, 0);
    if (data == MAP_FAILED) {
        close(fd);
        throw RuntimeError("cannot map the preview window's shared memory");
    }
    buffer->data = static_cast<uint8_t*>(data);
    wl_shm_pool* pool = wl_shm_create_pool(shm, fd, int32_t(buffer->size));
    buffer->buffer = wl_shm_pool_create_buffer(pool, 0, width, height, buffer->stride, WL_SHM_FORMAT_XRGB8888);
    wl_shm_pool_destroy(pool); // the buffer keeps the memory
    close(fd);
    wl_buffer_add_listener(buffer->buffer, &kBufferListener, buffer.get());
    return buffer;
}

} // namespace

struct WaylandWindow::State {
    wl_display* display = nullptr;
    wl_registry* registry = nullptr;
    wl_compositor* compositor = nullptr;
    wl_shm* shm = nullptr;
    xdg_wm_base* wmBase = nullptr;
    wl_seat* seat = nullptr;
    wl_keyboard* keyboard = nullptr;
    wl_surface* surface = nullptr;
    xdg_surface* xdgSurface = nullptr;
    xdg_toplevel* toplevel = nullptr;
    wl_egl_window* eglWindow = nullptr;
    xkb_context* xkb = nullptr;
    xkb_keymap* keymap = nullptr;
    xkb_state* keyState = nullptr;
    std::vector<std::unique_ptr<ShmBuffer>> buffers;
    ShmBuffer* writing = nullptr; // handed out by cpuPixels(), committed by showSwapped()
    uint64_t released = 0;

    bool configured = false; // the first xdg_surface.configure came
    int imposedWidth = 0;    // the toplevel's configured size; 0: ours to choose
    int imposedHeight = 0;
    int pendingWidth = 0, pendingHeight = 0; // until the xdg_surface.configure that applies them
    bool closeRequested = false;
    std::string typed;

    State() = default;
    State(const State&) = delete;
    State& operator=(const State&) = delete;
    ~State()
    {
        buffers.clear();
        if (eglWindow)
            wl_egl_window_destroy(eglWindow);
        if (toplevel)
            xdg_toplevel_destroy(toplevel);
        if (xdgSurface)
            xdg_surface_destroy(xdgSurface);
        if (surface)
            wl_surface_destroy(surface);
        if (keyboard)
            wl_keyboard_destroy(keyboard);
        if (seat)
            wl_seat_destroy(seat);
        if (wmBase)
            xdg_wm_base_destroy(wmBase);
        if (shm)
            wl_shm_destroy(shm);
        if (compositor)
            wl_compositor_destroy(compositor);
        if (registry)
            wl_registry_destroy(registry);
        if (keyState)
            xkb_state_unref(keyState);
        if (keymap)
            xkb_keymap_unref(keymap);
        if (xkb)
            xkb_context_unref(xkb);
        if (display) {
            wl_display_flush(display);
            wl_display_disconnect(display);
        }
    }

    [[nodiscard]] bool lost() const { return wl_display_get_error(display) != 0; }
    void throwIfLost() const
    {
        if (lost())
            throw RuntimeError("the Wayland display closed under the preview window");
    }

    // Reads and handles whatever events have arrived, without waiting for more.
    void dispatchPending()
    {
        if (lost())
            return;
        while (wl_display_prepare_read(display) != 0)
            if (wl_display_dispatch_pending(display) < 0)
                return;
        wl_display_flush(display);
        pollfd socket{wl_display_get_fd(display), POLLIN, 0};
        if (poll(&socket, 1, 0) > 0 && (socket.revents & POLLIN) != 0)
            wl_display_read_events(display);
        else
            wl_display_cancel_read(display);
        wl_display_dispatch_pending(display);
    }
};

namespace {

using State = WaylandWindow::State;

const wl_keyboard_listener kKeyboardListener = {
    .keymap =
        [](void* data, wl_keyboard*, uint32_t format, int32_t fd, uint32_t size) {
            auto& s = *static_cast<State*>(data);
            if (format == WL_KEYBOARD_KEYMAP_FORMAT_XKB_V1 && s.xkb) {
                void* text = mmap(nullptr, size, PROT_READ, MAP_PRIVATE, fd, 0);
                if (text != MAP_FAILED) {
                    xkb_keymap* keymap = xkb_keymap_new_from_string(
                        s.xkb, static_cast<const char*>(text), XKB_KEYMAP_FORMAT_TEXT_V1, XKB_KEYMAP_COMPILE_NO_FLAGS);
                    munmap(text, size);
                    if (keymap) {
                        if (s.keyState)
                            xkb_state_unref(s.keyState);
                        if (s.keymap)
                            xkb_keymap_unref(s.keymap);
                        s.keymap = keymap;
                        s.keyState = xkb_state_new(keymap);
                    }
                }
            }
            close(fd);
        },
    .enter = [](void*, wl_keyboard*, uint32_t, wl_surface*, wl_array*) {},
    .leave = [](void*, wl_keyboard*, uint32_t, wl_surface*) {},
    .key =
        [](void* data, wl_keyboard*, uint32_t, uint32_t, uint32_t key, uint32_t pressed) {
            auto& s = *static_cast<State*>(data);
            if (pressed != WL_KEYBOARD_KEY_STATE_PRESSED || !s.keyState)
                return;
            char text[16] = {};
            // Wayland sends evdev codes; xkb's are 8 higher (the X11 convention).
            const int length = xkb_state_key_get_utf8(s.keyState, key + 8, text, sizeof text);
            if (length > 0 && size_t(length) < sizeof text)
                s.typed.append(text, size_t(length));
        },
    .modifiers =
        [](void* data, wl_keyboard*, uint32_t, uint32_t depressed, uint32_t latched, uint32_t locked, uint32_t group) {
            auto& s = *static_cast<State*>(data);
            if (s.keyState)
                xkb_state_update_mask(s.keyState, depressed, latched, locked, 0, 0, group);
        },
    .repeat_info = [](void*, wl_keyboard*, int32_t, int32_t) {},
};

const wl_seat_listener kSeatListener = {
    .capabilities =
        [](void* data, wl_seat* seat, uint32_t capabilities) {
            auto& s = *static_cast<State*>(data);
            const bool has = (capabilities & WL_SEAT_CAPABILITY_KEYBOARD) != 0;
            if (has && !s.keyboard) {
                s.keyboard = wl_seat_get_keyboard(seat);
                wl_keyboard_add_listener(s.keyboard, &kKeyboardListener, &s);
            } else if (!has && s.keyboard) {
                wl_keyboard_destroy(s.keyboard);
                s.keyboard = nullptr;
            }
        },
    .name = [](void*, wl_seat*, const char*) {},
};

const xdg_wm_base_listener kWmBaseListener = {
    .ping = [](void*, xdg_wm_base* base, uint32_t serial) { xdg_wm_base_pong(base, serial); },
};

const xdg_surface_listener kXdgSurfaceListener = {
    .configure =
        [](void* data, xdg_surface* surface, uint32_t serial) {
            auto& s = *static_cast<State*>(data);
            s.imposedWidth = s.pendingWidth;
            s.imposedHeight = s.pendingHeight;
            s.configured = true;
            xdg_surface_ack_configure(surface, serial);
        },
};

const xdg_toplevel_listener kToplevelListener = {
    .configure =
        [](void* data, xdg_toplevel*, int32_t width, int32_t height, wl_array*) {
            auto& s = *static_cast<State*>(data);
            s.pendingWidth = std::max(0, width);
            s.pendingHeight = std::max(0, height);
        },
    .close = [](void* data, xdg_toplevel*) { static_cast<State*>(data)->closeRequested = true; },
    .configure_bounds = [](void*, xdg_toplevel*, int32_t, int32_t) {},
    .wm_capabilities = [](void*, xdg_toplevel*, wl_array*) {},
};

const wl_registry_listener kRegistryListener = {
    .global =
        [](void* data, wl_registry* registry, uint32_t name, const char* interface, uint32_t version) {
            auto& s = *static_cast<State*>(data);
            const std::string_view which = interface;
            if (which == wl_compositor_interface.name && !s.compositor)
                s.compositor = static_cast<wl_compositor*>(
                    wl_registry_bind(registry, name, &wl_compositor_interface, std::min(version, 4u)));
            else if (which == wl_shm_interface.name && !s.shm)
                s.shm = static_cast<wl_shm*>(wl_registry_bind(registry, name, &wl_shm_interface, 1));
            else if (which == xdg_wm_base_interface.name && !s.wmBase) {
                s.wmBase = static_cast<xdg_wm_base*>(wl_registry_bind(registry, name, &xdg_wm_base_interface, 1));
                xdg_wm_base_add_listener(s.wmBase, &kWmBaseListener, &s);
            } else if (which == wl_seat_interface.name && !s.seat) {
                s.seat =
                    static_cast<wl_seat*>(wl_registry_bind(registry, name, &wl_seat_interface, std::min(version, 4u)));
                wl_seat_add_listener(s.seat, &kSeatListener, &s);
            }
        },
    .global_remove = [](void*, wl_registry*, uint32_t) {},
};

} // namespace

std::unique_ptr<WaylandWindow> WaylandWindow::open(const std::string& displayName, const std::string& title, int width,
                                                   int height, std::string& why, WaylandPresentation presentation)
{
    auto window = std::unique_ptr<WaylandWindow>(new WaylandWindow());
    window->state_ = std::make_unique<State>();
    State& s = *window->state_;
    const char* fromEnvironment = std::getenv("WAYLAND_DISPLAY");
    const std::string name = displayName.empty() ? (fromEnvironment ? fromEnvironment : "") : displayName;
    s.display = wl_display_connect(displayName.empty() ? nullptr : displayName.c_str());
    if (!s.display) {
        why = name.empty() ? "WAYLAND_DISPLAY is not set" : "cannot connect to Wayland display '" + name + "'";
        return nullptr;
    }
    s.xkb = xkb_context_new(XKB_CONTEXT_NO_FLAGS);
    s.registry = wl_display_get_registry(s.display);
    wl_registry_add_listener(s.registry, &kRegistryListener, &s);
    // The globals, then what binding them sent (the seat's capabilities, the keymap).
    if (wl_display_roundtrip(s.display) < 0 || wl_display_roundtrip(s.display) < 0) {
        why = "the Wayland display closed while lumar asked for its globals";
        return nullptr;
    }
    if (!s.compositor || !s.wmBase) {
        why = "the Wayland compositor offers no xdg-shell";
        return nullptr;
    }

    s.surface = wl_compositor_create_surface(s.compositor);
    s.xdgSurface = xdg_wm_base_get_xdg_surface(s.wmBase, s.surface);
    xdg_surface_add_listener(s.xdgSurface, &kXdgSurfaceListener, &s);
    s.toplevel = xdg_surface_get_toplevel(s.xdgSurface);
    xdg_toplevel_add_listener(s.toplevel, &kToplevelListener, &s);
    xdg_toplevel_set_title(s.toplevel, title.c_str());
    xdg_toplevel_set_app_id(s.toplevel, "lumar");
    wl_surface_commit(s.surface);
    // Nothing may be attached before the first configure.
    while (!s.configured)
        if (wl_display_dispatch(s.display) < 0)
            throw RuntimeError("the Wayland display closed while opening the preview window");
    window->frameWidth_ = width;
    window->frameHeight_ = height;
    window->applySize();

    std::string eglWhy;
    try {
        window->eglDisplay_ = EglDisplay::wayland(s.display);
    } catch (const RuntimeError& e) {
        eglWhy = e.what();
    }
    const std::string driver = window->eglDisplay_ ? window->eglDisplay_->driverName() : "";
    const bool software = driver == "swrast" || driver == "kms_swrast";
    if (presentation == WaylandPresentation::SharedMemory || !window->eglDisplay_ ||
        (presentation == WaylandPresentation::Auto && software)) {
        if (!s.shm)
            throw RuntimeError("the Wayland compositor offers no wl_shm" +
                               (eglWhy.empty() ? std::string() : " and " + eglWhy));
        if (presentation == WaylandPresentation::EglSwap)
            throw RuntimeError(eglWhy);
        if (!window->eglDisplay_) {
            // Rendered on the surfaceless platform, shown from memory all the same.
            LUMAR_LOG(Output, Info) << "preview window: " << eglWhy << "; rendering surfaceless";
            window->eglDisplay_ = EglDisplay::surfaceless();
        }
        window->sharedMemory_ = true;
        LUMAR_LOG(Output, Info) << "preview window " << window->width_ << "x" << window->height_
                                << " on Wayland display " << name << " (EGL " << window->eglDisplay_->driverName()
                                << ", shown through wl_shm)";
        return window;
    }

    const EGLDisplay egl = window->eglDisplay_->handle();
    const EGLConfig config = chooseWindowConfig(
        egl, [](EGLint) { return 0; }, "Wayland", "no EGL window config on the Wayland display");
    s.eglWindow = wl_egl_window_create(s.surface, window->width_, window->height_);
    if (!s.eglWindow)
        throw RuntimeError("wl_egl_window_create failed");
    const auto createSurface = reinterpret_cast<PFNEGLCREATEPLATFORMWINDOWSURFACEEXTPROC>(
        eglGetProcAddress("eglCreatePlatformWindowSurfaceEXT"));
    if (!createSurface)
        throw RuntimeError("EGL lacks eglCreatePlatformWindowSurfaceEXT");
    window->surface_ = createSurface(egl, config, s.eglWindow, nullptr);
    if (window->surface_ == EGL_NO_SURFACE)
        throw RuntimeError("cannot create an EGL window surface on the Wayland window (EGL error " +
                           std::to_string(eglGetError()) + ")");
    window->eglDisplay_->setWindowConfig(config);
    LUMAR_LOG(Output, Info) << "preview window " << window->width_ << "x" << window->height_ << " on Wayland display "
                            << name << " (EGL " << driver << ")";
    return window;
}

WaylandWindow::~WaylandWindow()
{
    if (surface_ != EGL_NO_SURFACE) {
        if (eglGetCurrentSurface(EGL_DRAW) == surface_)
            eglMakeCurrent(eglDisplay_->handle(), EGL_NO_SURFACE, EGL_NO_SURFACE, eglGetCurrentContext());
        eglDestroySurface(eglDisplay_->handle(), surface_);
    }
    // EGL lets go of the connection before it closes.
    eglDisplay_.reset();
}

void WaylandWindow::applySize()
{
    const State& s = *state_;
    const int width = s.imposedWidth > 0 ? s.imposedWidth : frameWidth_;
    const int height = s.imposedHeight > 0 ? s.imposedHeight : frameHeight_;
    if (width == width_ && height == height_)
        return;
    width_ = width;
    height_ = height;
    if (s.eglWindow)
        wl_egl_window_resize(s.eglWindow, width, height, 0, 0);
}

void WaylandWindow::fitFrame(int width, int height)
{
    if (width <= 0 || height <= 0)
        return;
    frameWidth_ = width;
    frameHeight_ = height;
    applySize();
}

void WaylandWindow::pollEvents()
{
    state_->dispatchPending();
    state_->throwIfLost();
    applySize();
}

bool WaylandWindow::closeRequested() const
{
    return state_->closeRequested;
}

std::string WaylandWindow::takeTypedKeys()
{
    return std::exchange(state_->typed, {});
}

uint64_t WaylandWindow::framesReleased() const
{
    return state_->released;
}

std::optional<WindowTarget::CpuPixels> WaylandWindow::cpuPixels()
{
    if (!sharedMemory_)
        return std::nullopt;
    State& s = *state_;
    s.throwIfLost();
    // Buffers of an old size go once the compositor let go of them.
    std::erase_if(s.buffers, [&](const std::unique_ptr<ShmBuffer>& b) {
        return !b->busy && (b->width != width_ || b->height != height_);
    });
    // Three in flight at most: one shown, one queued, one written. Beyond that, wait for the
    // compositor to release one (it does once a newer one is shown).
    constexpr size_t kMaxBuffers = 3;
    const auto free = [&]() -> ShmBuffer* {
        for (const auto& b : s.buffers)
            if (!b->busy && b->width == width_ && b->height == height_)
                return b.get();
        return nullptr;
    };
    ShmBuffer* buffer = free();
    while (!buffer && s.buffers.size() >= kMaxBuffers) {
        if (wl_display_dispatch(s.display) < 0)
            s.throwIfLost();
        buffer = free();
    }
    if (!buffer) {
        s.buffers.push_back(makeShmBuffer(s.shm, width_, height_, &s.released));
        buffer = s.buffers.back().get();
    }
    s.writing = buffer;
    return CpuPixels{buffer->data, buffer->stride};
}

void WaylandWindow::showSwapped()
{
    State& s = *state_;
    ++framesShown_;
    if (sharedMemory_ && s.writing) {
        wl_surface_attach(s.surface, s.writing->buffer, 0, 0);
        if (wl_surface_get_version(s.surface) >= WL_SURFACE_DAMAGE_BUFFER_SINCE_VERSION)
            wl_surface_damage_buffer(s.surface, 0, 0, INT32_MAX, INT32_MAX);
        else
            wl_surface_damage(s.surface, 0, 0, INT32_MAX, INT32_MAX);
        wl_surface_commit(s.surface);
        s.writing->busy = true;
        s.writing = nullptr;
        // One round trip a frame: the compositor has taken this frame before the next is
        // rendered, so a slow compositor slows the loop down instead of queueing frames.
        wl_display_roundtrip(s.display);
    }
    pollEvents();
}

} // namespace lumar
