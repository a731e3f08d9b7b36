// CameraImage (gles_renderer/scene/camera_image.h): the camera image drawn into the frame's
// target is copied into a quarter-size texture that equals the image downsampled, row 0 at
// the image's top, for single-sampled and multisampled targets alike.
#include <vector>

#include <gtest/gtest.h>

#include "gl_test_support.h"
#include "gles_renderer/gl/gl_object.h"
#include "gles_renderer/gl/render_target.h"
#include "gles_renderer/scene/background_pass.h"
#include "gles_renderer/scene/camera_image.h"

namespace lumar {
namespace {

constexpr int kWidth = 160, kHeight = 120;

// A smooth gradient: red across, green down, blue along the diagonal.
Image8 gradient()
{
    Image8 image(kWidth, kHeight, 3);
    for (int y = 0; y < kHeight; ++y)
        for (int x = 0; x < kWidth; ++x) {
            uint8_t* p = image.at(x, y);
            p[0] = uint8_t(20 + x * 200 / kWidth);
            p[1] = uint8_t(10 + y * 220 / kHeight);
            p[2] = uint8_t(30 + (x + y) * 180 / (kWidth + kHeight));
        }
    return image;
}

// Level 0 of an RGBA8 texture, row 0 first.
std::vector<uint8_t> readRgba8(GLuint texture, int width, int height)
{
    GlFramebuffer framebuffer = GlFramebuffer::create();
    glBindFramebuffer(GL_READ_FRAMEBUFFER, framebuffer.name());
    glFramebufferTexture2D(GL_READ_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, texture, 0);
    std::vector<uint8_t> rgba(size_t(width) * size_t(height) * 4);
    glPixelStorei(GL_PACK_ALIGNMENT, 4);
    glReadPixels(0, 0, width, height, GL_RGBA, GL_UNSIGNED_BYTE, rgba.data());
    return rgba;
}

void expectDownsampled(int samples)
{
    LUMAR_RENDERER_OR_SKIP(renderer, kWidth, kHeight); // for its GL context
    (void)renderer;
    RenderTarget target(kWidth, kHeight, samples);
    BackgroundPass background(target);
    const Image8 image = gradient();
    target.bindForDrawing();
    background.draw(image);
    CameraImage camera(kWidth, kHeight);
    ASSERT_EQ(camera.width(), kWidth / 4);
    ASSERT_EQ(camera.height(), kHeight / 4);
    camera.capture(target);
    const std::vector<uint8_t> texels = readRgba8(camera.texture(), camera.width(), camera.height());
    int worst = 0;
    for (int ty = 0; ty < camera.height(); ++ty)
        for (int tx = 0; tx < camera.width(); ++tx)
            for (int c = 0; c < 3; ++c) {
                // The mean of the 4 x 4 pixels the texel covers.
                int sum = 0;
                for (int y = 4 * ty; y < 4 * ty + 4; ++y)
                    for (int x = 4 * tx; x < 4 * tx + 4; ++x)
                        sum += image.at(x, y)[c];
                const int expected = (sum + 8) / 16;
                const int got = texels[(size_t(ty) * size_t(camera.width()) + size_t(tx)) * 4 + size_t(c)];
                worst = std::max(worst, std::abs(got - expected));
            }
    EXPECT_LE(worst, 2) << "samples " << samples;
}

TEST(CameraImage, EqualsTheBackgroundDownsampled)
{
    expectDownsampled(1);
}

TEST(CameraImage, EqualsTheBackgroundDownsampledWhenMultisampled)
{
    expectDownsampled(4);
}

} // namespace
} // namespace lumar
