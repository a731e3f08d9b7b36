// The preview window on Wayland (gles_renderer/window/wayland_window.h) under a private
// headless weston: the window opens as an xdg-shell toplevel, takes the size the compositor
// imposes (the kiosk shell's full output), and the frames the renderer presents reach the
// compositor (it releases the shared-memory buffers it has taken). EGL's own Wayland path
// (eglSwapBuffers) runs on weston's X11 backend in a private Xvfb instead: Mesa 22.3's swrast
// swap never returns on headless weston 10, whose output sends no frame callbacks; there the
// frame is read back from the X server. Skips without weston (and Xvfb).
#include <cstdlib>
#include <vector>

#include <gtest/gtest.h>

#include "gl/weston_server.h"
#include "gl/x11_viewer.h"
#include "gl/xvfb_server.h"
#include "gl_test_support.h"
#include "gles_renderer/window/wayland_window.h"

namespace lumar {
namespace {

constexpr int kOutputWidth = 320, kOutputHeight = 240;

class WaylandWindowTest : public ::testing::Test {
protected:
    void SetUp() override
    {
        if (!test::WestonServer::installed())
            GTEST_SKIP() << "weston is not installed (apt-get install weston)";
        server_ = std::make_unique<test::WestonServer>(kOutputWidth, kOutputHeight);
        if (server_->socket().empty())
            GTEST_SKIP() << "weston did not start on its headless backend";
    }

    std::unique_ptr<test::WestonServer> server_;
};

TEST_F(WaylandWindowTest, PresentedFramesReachTheCompositorInTheImposedSize)
{
    const int width = 160, height = 120;
    std::string why;
    auto window =
        WaylandWindow::open(server_->socket(), "lumar test", width, height, why, WaylandPresentation::SharedMemory);
    ASSERT_NE(window, nullptr) << why;
    EXPECT_TRUE(window->presentsFromMemory());
    // The kiosk shell makes the toplevel fill its output.
    EXPECT_EQ(window->width(), kOutputWidth);
    EXPECT_EQ(window->height(), kOutputHeight);
    window->fitFrame(width, height); // the compositor's size stands
    EXPECT_EQ(window->width(), kOutputWidth);

    RenderOptions options;
    options.display = window->eglDisplay();
    auto rendererOrReason = test::tryCreateRenderer(width, height, options);
    if (!rendererOrReason.renderer)
        GTEST_SKIP() << "no GLES 3 renderer: " << rendererOrReason.reason;
    SceneRenderer& renderer = *rendererOrReason.renderer;
    const CameraIntrinsics k = test::makeIntrinsics(width, height, 150, 150, width / 2.0, height / 2.0);
    for (int i = 0; i < 4; ++i) {
        renderer.render(test::solidImage(width, height, 200, 100, 50), k, {});
        renderer.present(*window);
    }
    EXPECT_EQ(window->framesShown(), 4u);
    // Each frame taken by the compositor is released once a newer one is shown.
    for (int i = 0; i < 100 && window->framesReleased() < 3; ++i) {
        window->pollEvents();
        usleep(10000);
    }
    EXPECT_GE(window->framesReleased(), 3u);
    EXPECT_FALSE(window->closeRequested());
    EXPECT_EQ(window->takeTypedKeys(), "");
}

TEST_F(WaylandWindowTest, OnASoftwareRasteriserFramesGoThroughSharedMemory)
{
    std::string why;
    auto window = WaylandWindow::open(server_->socket(), "lumar test", 64, 48, why);
    ASSERT_NE(window, nullptr) << why;
    const std::string& driver = window->eglDisplay()->driverName();
    if (driver != "swrast" && driver != "kms_swrast" && !window->presentsFromMemory())
        GTEST_SKIP() << "EGL driver " << driver << " draws on Wayland itself";
    EXPECT_TRUE(window->presentsFromMemory());
    EXPECT_EQ(window->surface(), EGL_NO_SURFACE);
}

// EGL's own Wayland path (eglSwapBuffers into a wl_egl_window), on weston's X11 backend inside
// a private Xvfb: a compositor whose output repaints, so frame callbacks come.
TEST(WaylandWindowEgl, ThroughEglsWindowSurfaceWhereEglReachesTheCompositor)
{
    if (!test::WestonServer::installed() || !test::XvfbServer::installed())
        GTEST_SKIP() << "weston or Xvfb is not installed (apt-get install weston xvfb)";
    test::XvfbServer xvfb(640, 480);
    ASSERT_FALSE(xvfb.display().empty()) << "Xvfb did not start";
    test::WestonServer server(kOutputWidth, kOutputHeight, xvfb.display());
    ASSERT_FALSE(server.socket().empty()) << "weston did not start on its X11 backend";
    const int width = 160, height = 120;
    std::string why;
    std::unique_ptr<WaylandWindow> window;
    try {
        window = WaylandWindow::open(server.socket(), "lumar test", width, height, why, WaylandPresentation::EglSwap);
    } catch (const RuntimeError& e) {
        GTEST_SKIP() << "no EGL window surface on weston: " << e.what();
    }
    ASSERT_NE(window, nullptr) << why;
    ASSERT_NE(window->surface(), EGL_NO_SURFACE);
    RenderOptions options;
    options.display = window->eglDisplay();
    auto rendererOrReason = test::tryCreateRenderer(width, height, options);
    if (!rendererOrReason.renderer)
        GTEST_SKIP() << "no GLES 3 renderer: " << rendererOrReason.reason;
    const CameraIntrinsics k = test::makeIntrinsics(width, height, 150, 150, width / 2.0, height / 2.0);
    for (int i = 0; i < 3; ++i) {
        rendererOrReason.renderer->render(test::solidImage(width, height, 20, 100, 250), k, {});
        rendererOrReason.renderer->present(*window);
    }
    EXPECT_EQ(window->framesShown(), 3u);
    // The frame reached weston's output: its X window, read back from the X server, shows the
    // rendered colour (the frame is scaled to the kiosk's full output, so its centre).
    Image8 rendered;
    rendererOrReason.renderer->readback(rendered);
    const uint8_t* expected = &rendered.data[(size_t(height / 2) * width + width / 2) * rendered.channels];
    test::X11Viewer viewer(xvfb.display());
    ASSERT_TRUE(viewer.connected());
    const unsigned long output = viewer.findWindow(test::WestonServer::x11WindowTitle());
    ASSERT_NE(output, 0u);
    std::vector<uint8_t> shown;
    const auto centreMatches = [&] {
        window->pollEvents();
        shown = viewer.grab(output, kOutputWidth, kOutputHeight);
        if (shown.empty())
            return false;
        const uint8_t* p = &shown[(size_t(kOutputHeight / 2) * kOutputWidth + kOutputWidth / 2) * 3];
        for (int c = 0; c < 3; ++c)
            if (std::abs(int(p[c]) - int(expected[c])) > 1)
                return false;
        return true;
    };
    EXPECT_TRUE(test::waitUntil(centreMatches, std::chrono::seconds(20)))
        << "rendered " << int(expected[0]) << "," << int(expected[1]) << "," << int(expected[2]);
}

TEST(WaylandWindowOpen, NoCompositorIsNoWindowAndSaysWhy)
{
    std::string why;
    auto window = WaylandWindow::open("/nonexistent/wayland-9", "lumar test", 64, 48, why);
    EXPECT_EQ(window, nullptr);
    EXPECT_NE(why.find("/nonexistent/wayland-9"), std::string::npos) << why;
}

} // namespace
} // namespace lumar
