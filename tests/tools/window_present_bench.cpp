// The preview window's cost per frame: SceneRenderer::present() into an X11 window through
// EGL's window surface (blit, eglSwapBuffers, one X round trip) and through MIT-SHM (read back
// into the shared image, XShmPutImage, one round trip), against readback() (what the headless
// sink pays), at 1280x720 on a private Xvfb. Interleaved rounds, medians. Not a test.
//
//   build/tests/tools/window_present_bench [rounds] [frames]   (defaults 5 rounds of 60 frames)
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <string>
#include <vector>

#include "gl/xvfb_server.h"
#include "gles_renderer/scene/scene_renderer.h"
#include "gles_renderer/window/x11_window.h"

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

    using Clock = std::chrono::steady_clock;
    std::vector<double> swapMs, shmMs, readbackMs;
    lumar::Image8 out;
    for (int round = 0; round < rounds; ++round) {
        for (int pass = 0; pass < 3; ++pass) {
            const auto start = Clock::now();
            for (int i = 0; i < frames; ++i) {
                if (pass == 0)
                    swap.renderer->present(*swap.window);
                else if (pass == 1)
                    shm.renderer->present(*shm.window);
                else
                    shm.renderer->readback(out);
            }
            const double ms = std::chrono::duration<double, std::milli>(Clock::now() - start).count() / frames;
            (pass == 0 ? swapMs : pass == 1 ? shmMs : readbackMs).push_back(ms);
        }
    }
    std::printf("%dx%d, %d rounds of %d frames, medians per frame: EGL swap %.2f ms, MIT-SHM %.2f ms, headless "
                "readback %.2f ms (swap/shm %.1fx)\n",
                width, height, rounds, frames, median(swapMs), median(shmMs), median(readbackMs),
                median(swapMs) / median(shmMs));
    return 0;
}
