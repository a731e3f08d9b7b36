// The preview window's cost per frame: SceneRenderer::present() into an X11 window (blit,
// eglSwapBuffers, one X round trip) against readback() (what the headless sink pays), at
// 1280x720 on a private Xvfb. Interleaved rounds, medians. Not a test.
//
//   build/tests/tools/window_present_bench [rounds] [frames]   (defaults 5 rounds of 60 frames)
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
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
    std::string why;
    auto window = lumar::X11Window::open(server.display(), "bench", width, height, why);
    if (!window) {
        std::fprintf(stderr, "no window: %s\n", why.c_str());
        return 1;
    }
    lumar::RenderOptions options;
    options.display = window->eglDisplay();
    auto renderer = lumar::SceneRenderer::create(width, height, options);
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
    renderer->render(background, k, {});

    using Clock = std::chrono::steady_clock;
    std::vector<double> presentMs, readbackMs;
    lumar::Image8 out;
    for (int round = 0; round < rounds; ++round) {
        for (int pass = 0; pass < 2; ++pass) {
            const auto start = Clock::now();
            for (int i = 0; i < frames; ++i) {
                if (pass == 0)
                    renderer->present(*window);
                else
                    renderer->readback(out);
            }
            const double ms = std::chrono::duration<double, std::milli>(Clock::now() - start).count() / frames;
            (pass == 0 ? presentMs : readbackMs).push_back(ms);
        }
    }
    std::printf("%dx%d, %d rounds of %d frames, medians: present %.2f ms/frame, readback %.2f ms/frame (ratio %.2f)\n",
                width, height, rounds, frames, median(presentMs), median(readbackMs),
                median(presentMs) / median(readbackMs));
    return 0;
}
