// The preview window's cost per frame: SceneRenderer::present() into an X11 window through
// EGL's window surface (blit, eglSwapBuffers, one X round trip) and through MIT-SHM (read back
// into the shared image, XShmPutImage, one round trip), against readback() (what the headless
// sink pays), at 1280x720 on a private Xvfb; with Wayland built in and weston installed, also
// into a Wayland window on weston's X11 backend in the same Xvfb (shared memory: read back
// into a wl_shm buffer, attach, commit, one round trip). Interleaved rounds, medians. Not a
// test.
//
//   build/tests/tools/window_present_bench [rounds] [frames]   (defaults 5 rounds of 60 frames)
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <string>
#include <vector>

#include "gl/weston_server.h"
#include "gl/xvfb_server.h"
#include "gles_renderer/scene/scene_renderer.h"
#include "gles_renderer/window/x11_window.h"
#if LUMAR_HAVE_WAYLAND
#include "gles_renderer/window/wayland_window.h"
#endif

namespace {

double median(std::vector<double> v)
{
    std::sort(v.begin(), v.end());
    return v[v.size() / 2];
}

} // namespace

namespace {

struct Setup {
    std::unique_ptr<lumar::X11Window> window;
    std::unique_ptr<lumar::SceneRenderer> renderer;
};

Setup open(const std::string& display, lumar::X11Presentation presentation, const lumar::Image8& background,
           const lumar::CameraIntrinsics& k)
{
    Setup s;
    std::string why;
    s.window = lumar::X11Window::open(display, "bench", k.width, k.height, why, presentation);
    if (!s.window) {
        std::fprintf(stderr, "no window: %s\n", why.c_str());
        std::exit(1);
    }
    lumar::RenderOptions options;
    options.display = s.window->eglDisplay();
    s.renderer = lumar::SceneRenderer::create(k.width, k.height, options);
    s.renderer->render(background, k, {});
    return s;
}

#if LUMAR_HAVE_WAYLAND
struct WaylandSetup {
    std::unique_ptr<lumar::test::WestonServer> weston;
    std::unique_ptr<lumar::WaylandWindow> window;
    std::unique_ptr<lumar::SceneRenderer> renderer;
};

// A Wayland window on a weston of its own (X11 backend, pixman) in the X server `display`;
// no window (and a line saying why) where that cannot be had.
WaylandSetup openWayland(const std::string& display, lumar::WaylandPresentation presentation,
                         const lumar::Image8& background, const lumar::CameraIntrinsics& k)
{
    WaylandSetup s;
    s.weston = std::make_unique<lumar::test::WestonServer>(k.width, k.height, display);
    std::string why = "weston did not start";
    try {
        if (!s.weston->socket().empty())
            s.window = lumar::WaylandWindow::open(s.weston->socket(), "bench", k.width, k.height, why, presentation);
    } catch (const std::exception& e) {
        why = e.what();
    }
    if (!s.window) {
        std::fprintf(stderr, "no Wayland window on weston (X11 backend): %s\n", why.c_str());
        return s;
    }
    lumar::RenderOptions options;
    options.display = s.window->eglDisplay();
    s.renderer = lumar::SceneRenderer::create(k.width, k.height, options);
    s.renderer->render(background, k, {});
    return s;
}
#endif

} // namespace

int main(int argc, char** argv)
{
    const int rounds = argc > 1 ? std::atoi(argv[1]) : 5;
    const int frames = argc > 2 ? std::atoi(argv[2]) : 60;
    const int width = 1280, height = 720;
    lumar::test::XvfbServer server(1920, 1080);
    if (server.display().empty()) {
        std::fprintf(stderr, "Xvfb did not start\n");
        return 1;
    }
    lumar::Image8 background;
    background.width = width;
    background.height = height;
    background.channels = 3;
    background.data.resize(size_t(width) * height * 3);
    for (size_t i = 0; i < background.data.size(); ++i)
        background.data[i] = uint8_t(i * 7 % 251);
    lumar::CameraIntrinsics k;
    k.width = width;
    k.height = height;
    k.fx = k.fy = 1000;
    k.cx = width / 2.0;
    k.cy = height / 2.0;
    Setup swap = open(server.display(), lumar::X11Presentation::EglSwap, background, k);
    Setup shm = open(server.display(), lumar::X11Presentation::SharedMemory, background, k);
    if (!shm.window->presentsFromMemory())
        std::fprintf(stderr, "MIT-SHM refused: the second column is the EGL swap too\n");
#if LUMAR_HAVE_WAYLAND
    // One weston each (an EGL swap waits for frame callbacks, which a window hidden behind
    // another in the kiosk shell would not get); its output is the frame's size, so the kiosk
    // shell's full-output window takes the frame as it is, no scaling.
    WaylandSetup waylandShm, waylandSwap;
    if (lumar::test::WestonServer::installed()) {
        waylandShm = openWayland(server.display(), lumar::WaylandPresentation::SharedMemory, background, k);
        waylandSwap = openWayland(server.display(), lumar::WaylandPresentation::EglSwap, background, k);
    }
#endif

    // The setup view of four tags (outline, axes, label each) and a status line, drawn before
    // the readback in the fourth column: its cost is that column less the third.
    lumar::OverlayScene overlay;
    for (int t = 0; t < 4; ++t) {
        const glm::dvec2 c(200.0 + 250.0 * t, 360.0);
        const glm::dvec2 corners[4] = {c + glm::dvec2(-80, -70), c + glm::dvec2(80, -60), c + glm::dvec2(70, 80),
                                       c + glm::dvec2(-75, 70)};
        for (int i = 0; i < 4; ++i)
            overlay.lines.push_back({corners[i], corners[(i + 1) % 4], {40, 255, 80, 255}, 2.0f});
        for (int a = 0; a < 3; ++a)
            overlay.lines.push_back({c, c + glm::dvec2(40.0 * (a == 0), -40.0 * (a == 1)), {255, 40, 40, 255}, 2.0f});
        overlay.texts.push_back({c + glm::dvec2(-40, 90), "id 3  0.25 px", {40, 255, 80, 255}, {0, 0, 0, 170}, 1, 2});
    }
    overlay.texts.push_back({{6, 6},
                             "frame 1234  markers 4  objects 2  30.0 fps  latency p50 45 ms  camera ok",
                             {255, 255, 255, 255},
                             {0, 0, 0, 170},
                             1,
                             3});

    using Clock = std::chrono::steady_clock;
    std::vector<double> swapMs, shmMs, readbackMs, overlayMs, waylandShmMs, waylandSwapMs;
    lumar::Image8 out;
    for (int round = 0; round < rounds; ++round) {
        for (int pass = 0; pass < 6; ++pass) {
#if LUMAR_HAVE_WAYLAND
            WaylandSetup& wayland = pass == 4 ? waylandShm : waylandSwap;
            if (pass >= 4 && !wayland.window)
                continue;
#else
            if (pass >= 4)
                continue;
#endif
            const auto start = Clock::now();
            for (int i = 0; i < frames; ++i) {
                if (pass == 0)
                    swap.renderer->present(*swap.window);
                else if (pass == 1)
                    shm.renderer->present(*shm.window);
                else if (pass == 2)
                    shm.renderer->readback(out);
                else if (pass == 3) {
                    shm.renderer->drawOverlay(overlay);
                    shm.renderer->readback(out);
                }
#if LUMAR_HAVE_WAYLAND
                else
                    wayland.renderer->present(*wayland.window);
#endif
            }
            const double ms = std::chrono::duration<double, std::milli>(Clock::now() - start).count() / frames;
            (pass == 0   ? swapMs
             : pass == 1 ? shmMs
             : pass == 2 ? readbackMs
             : pass == 3 ? overlayMs
             : pass == 4 ? waylandShmMs
                         : waylandSwapMs)
                .push_back(ms);
        }
    }
    std::printf("%dx%d, %d rounds of %d frames, medians per frame: EGL swap %.2f ms, MIT-SHM %.2f ms, headless "
                "readback %.2f ms (swap/shm %.1fx); overlay + readback %.2f ms\n",
                width, height, rounds, frames, median(swapMs), median(shmMs), median(readbackMs),
                median(swapMs) / median(shmMs), median(overlayMs));
    // Wayland's present() waits for weston to have taken the commit (a round trip), not for it
    // to have composited and drawn it into its X window.
    if (!waylandShmMs.empty())
        std::printf("Wayland (weston 10, X11 backend, pixman): wl_shm %.2f ms per frame\n", median(waylandShmMs));
    if (!waylandSwapMs.empty())
        std::printf("Wayland (weston 10, X11 backend, pixman): EGL swap %.2f ms per frame\n", median(waylandSwapMs));
    return 0;
}
