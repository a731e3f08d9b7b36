// The preview window (gles_renderer/window/x11_window.h) under a private Xvfb: the frame the
// renderer presents arrives in the window as the X server holds it (read back with XGetImage
// on a connection of the test's own, not from lumar's buffers) equal to the frame the
// headless sink reads back (+-1); a resized window shows the frame fitted with its aspect
// kept; the window manager's close request is seen.
#include <cstdlib>

#include <gtest/gtest.h>
#include <unistd.h>

#include "gl/x11_viewer.h"
#include "gl/xvfb_server.h"
#include "gl_test_support.h"
#include "gles_renderer/window/x11_window.h"

namespace lumar {
namespace {

// A frame with structure in every direction: a colour ramp with a bright square off-centre.
Image8 testFrame(int width, int height)
{
    Image8 image = test::solidImage(width, height, 0, 0, 0);
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x) {
            uint8_t* p = &image.data[(size_t(y) * size_t(width) + size_t(x)) * 3];
            const bool square = x > width / 5 && x < width / 3 && y > height / 6 && y < height / 2;
            p[0] = square ? 255 : uint8_t(255 * x / (width - 1));
            p[1] = square ? 255 : uint8_t(255 * y / (height - 1));
            p[2] = uint8_t(40 + (x * 7 + y * 3) % 160);
        }
    return image;
}

class WindowTest : public ::testing::Test {
protected:
    void SetUp() override
    {
        if (std::system("command -v Xvfb >/dev/null 2>&1") != 0)
            GTEST_SKIP() << "Xvfb is not installed (apt-get install xvfb)";
        if (server_.display().empty())
            GTEST_SKIP() << "Xvfb did not start";
        viewer_ = std::make_unique<test::X11Viewer>(server_.display());
        ASSERT_TRUE(viewer_->connected());
    }

    void presentedFramesArriveEqualToTheHeadlessFrame(X11Presentation presentation);
    void aResizedWindowShowsTheFrameWithItsAspectKept(X11Presentation presentation);

    test::XvfbServer server_;
    std::unique_ptr<test::X11Viewer> viewer_; // the test's own connection: what anyone sees on the server
};

TEST_F(WindowTest, PresentedFramesArriveEqualToTheHeadlessFrame)
{
    // Through EGL's window surface and through MIT-SHM (the default on llvmpipe) alike.
    for (const X11Presentation presentation : {X11Presentation::EglSwap, X11Presentation::SharedMemory}) {
        SCOPED_TRACE(presentation == X11Presentation::EglSwap ? "EGL swap" : "MIT-SHM");
        presentedFramesArriveEqualToTheHeadlessFrame(presentation);
    }
}

TEST_F(WindowTest, OnASoftwareRasteriserFramesGoThroughSharedMemory)
{
    std::string why;
    auto window = X11Window::open(server_.display(), "lumar test", 64, 48, why);
    ASSERT_NE(window, nullptr) << why;
    const std::string& driver = window->eglDisplay()->driverName();
    if (driver != "swrast" && driver != "kms_swrast")
        GTEST_SKIP() << "EGL driver " << driver << " is not a software rasteriser";
    EXPECT_TRUE(window->presentsFromMemory());
    EXPECT_EQ(window->surface(), EGL_NO_SURFACE);
}

TEST_F(WindowTest, TypedKeysReachTheWindow)
{
    std::string why;
    auto window = X11Window::open(server_.display(), "lumar test", 64, 48, why);
    ASSERT_NE(window, nullptr) << why;
    viewer_->typeKey(window->windowId(), 'o');
    std::string typed;
    for (int i = 0; i < 200 && typed.empty(); ++i) {
        window->pollEvents();
        typed += window->takeTypedKeys();
        usleep(5000);
    }
    EXPECT_EQ(typed, "o");
    EXPECT_EQ(window->takeTypedKeys(), "");
}

void WindowTest::presentedFramesArriveEqualToTheHeadlessFrame(X11Presentation presentation)
{
    const int width = 320, height = 180;
    std::string why;
    auto window = X11Window::open(server_.display(), "lumar test", width, height, why, presentation);
    ASSERT_NE(window, nullptr) << why;
    RenderOptions options;
    options.display = window->eglDisplay();
    auto rendererOrReason = test::tryCreateRenderer(width, height, options);
    if (!rendererOrReason.renderer)
        GTEST_SKIP() << "no GLES 3 renderer: " << rendererOrReason.reason;
    SceneRenderer& renderer = *rendererOrReason.renderer;
    const Image8 frame = testFrame(width, height);
    const CameraIntrinsics k = test::makeIntrinsics(width, height, 300, 300, width / 2.0, height / 2.0);

    for (int i = 0; i < 3; ++i) {
        renderer.render(frame, k, {});
        Image8 headless;
        renderer.readback(headless);
        renderer.present(*window);
        const std::vector<uint8_t> shown = viewer_->grab(window->windowId(), width, height);
        ASSERT_EQ(shown.size(), headless.data.size());
        int worst = 0;
        for (size_t j = 0; j < shown.size(); ++j)
            worst = std::max(worst, std::abs(int(shown[j]) - int(headless.data[j])));
        EXPECT_LE(worst, 1) << "frame " << i;
    }
    EXPECT_EQ(window->framesShown(), 3u);
}

TEST_F(WindowTest, AResizedWindowShowsTheFrameWithItsAspectKept)
{
    for (const X11Presentation presentation : {X11Presentation::EglSwap, X11Presentation::SharedMemory}) {
        SCOPED_TRACE(presentation == X11Presentation::EglSwap ? "EGL swap" : "MIT-SHM");
        aResizedWindowShowsTheFrameWithItsAspectKept(presentation);
    }
}

void WindowTest::aResizedWindowShowsTheFrameWithItsAspectKept(X11Presentation presentation)
{
    const int width = 160, height = 120;
    std::string why;
    auto window = X11Window::open(server_.display(), "lumar test", width, height, why, presentation);
    ASSERT_NE(window, nullptr) << why;
    RenderOptions options;
    options.display = window->eglDisplay();
    auto rendererOrReason = test::tryCreateRenderer(width, height, options);
    if (!rendererOrReason.renderer)
        GTEST_SKIP() << "no GLES 3 renderer: " << rendererOrReason.reason;
    SceneRenderer& renderer = *rendererOrReason.renderer;
    const CameraIntrinsics k = test::makeIntrinsics(width, height, 150, 150, width / 2.0, height / 2.0);

    viewer_->resize(window->windowId(), 480, 120);
    // The new size reaches the window with its events, at the next present.
    for (int i = 0; i < 3; ++i) {
        renderer.render(test::solidImage(width, height, 200, 100, 50), k, {});
        renderer.present(*window);
    }
    ASSERT_EQ(window->width(), 480);
    ASSERT_EQ(window->height(), 120);
    const std::vector<uint8_t> shown = viewer_->grab(window->windowId(), 480, 120);
    ASSERT_EQ(shown.size(), size_t(480 * 120 * 3));
    const auto pixel = [&shown](int x, int y) {
        const size_t i = (size_t(y) * 480 + size_t(x)) * 3;
        return std::array<int, 3>{shown[i], shown[i + 1], shown[i + 2]};
    };
    // Scale min(480/160, 120/120) = 1: the frame at x = 160..319, black bars beside it.
    EXPECT_EQ(pixel(80, 60), (std::array<int, 3>{0, 0, 0}));
    EXPECT_EQ(pixel(400, 60), (std::array<int, 3>{0, 0, 0}));
    EXPECT_EQ(pixel(161, 1), (std::array<int, 3>{200, 100, 50}));
    EXPECT_EQ(pixel(318, 118), (std::array<int, 3>{200, 100, 50}));
}

TEST_F(WindowTest, TheWindowManagersCloseRequestIsSeen)
{
    std::string why;
    auto window = X11Window::open(server_.display(), "lumar test", 64, 48, why);
    ASSERT_NE(window, nullptr) << why;
    window->pollEvents();
    EXPECT_FALSE(window->closeRequested());
    viewer_->requestClose(window->windowId());
    for (int i = 0; i < 200 && !window->closeRequested(); ++i) {
        window->pollEvents();
        usleep(5000);
    }
    EXPECT_TRUE(window->closeRequested());
}

TEST(WindowOpen, NoServerIsNoWindowAndSaysWhy)
{
    std::string why;
    auto window = X11Window::open(":59999", "lumar test", 64, 48, why);
    EXPECT_EQ(window, nullptr);
    EXPECT_NE(why.find(":59999"), std::string::npos) << why;
}

} // namespace
} // namespace lumar
