// SceneRenderer::present(): the finished frame copied into a window surface, fitted with its
// aspect kept (black bars), upright, and handed to the window after the swap. A pbuffer on
// the surfaceless display stands in for the KMS display's GBM window surface (the same blit
// and swap; the KMS flip itself runs in the virtual-board system test).
#include <array>
#include <cstdint>

#include <EGL/egl.h>
#include <GLES3/gl3.h>
#include <gtest/gtest.h>

#include "gl_test_support.h"
#include "gles_renderer/gl/egl_context.h"
#include "gles_renderer/gl/window_target.h"

namespace lumar {
namespace {

class PbufferWindow final : public WindowTarget {
public:
    PbufferWindow(std::shared_ptr<EglDisplay> display, int width, int height)
        : display_(std::move(display)), width_(width), height_(height)
    {
        const EGLint attributes[] = {EGL_SURFACE_TYPE,
                                     EGL_PBUFFER_BIT,
                                     EGL_RENDERABLE_TYPE,
                                     EGL_OPENGL_ES3_BIT,
                                     EGL_RED_SIZE,
                                     8,
                                     EGL_GREEN_SIZE,
                                     8,
                                     EGL_BLUE_SIZE,
                                     8,
                                     EGL_NONE};
        EGLConfig config = nullptr;
        EGLint count = 0;
        if (!eglChooseConfig(display_->handle(), attributes, &config, 1, &count) || count < 1)
            return;
        const EGLint size[] = {EGL_WIDTH, width, EGL_HEIGHT, height, EGL_NONE};
        surface_ = eglCreatePbufferSurface(display_->handle(), config, size);
    }
    ~PbufferWindow() override
    {
        if (surface_ != EGL_NO_SURFACE) {
            eglMakeCurrent(display_->handle(), EGL_NO_SURFACE, EGL_NO_SURFACE, eglGetCurrentContext());
            eglDestroySurface(display_->handle(), surface_);
        }
    }
    PbufferWindow(const PbufferWindow&) = delete;
    PbufferWindow& operator=(const PbufferWindow&) = delete;

    [[nodiscard]] const std::shared_ptr<EglDisplay>& eglDisplay() const override { return display_; }
    [[nodiscard]] EGLSurface surface() const override { return surface_; }
    [[nodiscard]] int width() const override { return width_; }
    [[nodiscard]] int height() const override { return height_; }
    void showSwapped() override { ++shown; }

    int shown = 0;

private:
    std::shared_ptr<EglDisplay> display_;
    int width_, height_;
    EGLSurface surface_ = EGL_NO_SURFACE;
};

using Rgb = std::array<int, 3>;

// The window's pixel at (x, y), y counted from the window's top.
Rgb windowPixel(int x, int yFromTop, int height)
{
    std::array<uint8_t, 4> rgba{};
    glBindFramebuffer(GL_READ_FRAMEBUFFER, 0);
    glReadPixels(x, height - 1 - yFromTop, 1, 1, GL_RGBA, GL_UNSIGNED_BYTE, rgba.data());
    return {rgba[0], rgba[1], rgba[2]};
}

void expectNear(const Rgb& actual, const Rgb& expected, const char* where)
{
    for (int c = 0; c < 3; ++c)
        EXPECT_NEAR(actual[size_t(c)], expected[size_t(c)], 2) << where << " channel " << c;
}

TEST(Present, FitsTheFrameUprightWithBlackBars)
{
    std::shared_ptr<EglDisplay> display;
    try {
        display = EglDisplay::surfaceless();
    } catch (const RuntimeError& e) {
        GTEST_SKIP() << "no EGL: " << e.what();
    }
    RenderOptions options;
    options.display = display;
    LUMAR_RENDERER_OR_SKIP(renderer, 64, 48, options);
    PbufferWindow window(display, 200, 100);
    if (window.surface() == EGL_NO_SURFACE)
        GTEST_SKIP() << "no pbuffer surface on the surfaceless display";

    // Top half red with a green top-left quarter, bottom half blue.
    Image8 background = test::solidImage(64, 48, 0, 0, 255);
    for (int y = 0; y < 24; ++y)
        for (int x = 0; x < 64; ++x) {
            uint8_t* p = &background.data[(size_t(y) * 64 + size_t(x)) * 3];
            p[0] = x < 32 ? 0 : 255;
            p[1] = x < 32 ? 255 : 0;
            p[2] = 0;
        }
    renderer.render(background, test::makeIntrinsics(64, 48, 60, 60, 32, 24), {});
    renderer.present(window);
    EXPECT_EQ(window.shown, 1);

    // Scale min(200/64, 100/48) = 2.083: the frame is 133x100 at x = 33..166.
    expectNear(windowPixel(5, 50, 100), {0, 0, 0}, "left bar");
    expectNear(windowPixel(195, 50, 100), {0, 0, 0}, "right bar");
    expectNear(windowPixel(40, 5, 100), {0, 255, 0}, "top left");
    expectNear(windowPixel(160, 5, 100), {255, 0, 0}, "top right");
    expectNear(windowPixel(40, 95, 100), {0, 0, 255}, "bottom left");
    expectNear(windowPixel(160, 95, 100), {0, 0, 255}, "bottom right");

    // The renderer keeps drawing into its own framebuffers with the window bound.
    renderer.render(test::solidImage(64, 48, 255, 255, 255), test::makeIntrinsics(64, 48, 60, 60, 32, 24), {});
    renderer.present(window);
    EXPECT_EQ(window.shown, 2);
    expectNear(windowPixel(100, 50, 100), {255, 255, 255}, "second frame");
    Image8 readBack;
    renderer.readback(readBack);
    ASSERT_EQ(readBack.width, 64);
    EXPECT_EQ(readBack.data[0], 255);
}

} // namespace
} // namespace lumar
