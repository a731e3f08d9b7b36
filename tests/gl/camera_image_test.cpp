// CameraImage (gles_renderer/scene/camera_image.h): the camera image drawn into the frame's
// target is copied into a quarter-size texture that equals the image downsampled, row 0 at
// the image's top, for single-sampled and multisampled targets alike; the CPU reduction of the
// frame gives the GPU's texture at every mip level.
#include <algorithm>
#include <bit>
#include <cstdlib>
#include <random>
#include <string>
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

// A level of an RGBA8 texture, row 0 first.
std::vector<uint8_t> readRgba8(GLuint texture, int width, int height, int level = 0)
{
    GlFramebuffer framebuffer = GlFramebuffer::create();
    glBindFramebuffer(GL_READ_FRAMEBUFFER, framebuffer.name());
    glFramebufferTexture2D(GL_READ_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, texture, level);
    std::vector<uint8_t> rgba(size_t(width) * size_t(height) * 4);
    glPixelStorei(GL_PACK_ALIGNMENT, 4);
    glReadPixels(0, 0, width, height, GL_RGBA, GL_UNSIGNED_BYTE, rgba.data());
    return rgba;
}

void expectDownsampled(int samples, bool onCpu = false)
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
    if (onCpu) {
        camera.reduce(image);
        camera.uploadReduced();
    } else {
        camera.capture(target);
    }
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
    EXPECT_LE(worst, 2) << "samples " << samples << (onCpu ? ", on the CPU" : "");
}

TEST(CameraImage, EqualsTheBackgroundDownsampled)
{
    expectDownsampled(1);
}

TEST(CameraImage, EqualsTheBackgroundDownsampledWhenMultisampled)
{
    expectDownsampled(4);
}

TEST(CameraImage, EqualsTheBackgroundDownsampledOnTheCpu)
{
    expectDownsampled(1, true);
}

// Noise is the hardest image for a resampler to agree on: every texel differs from its
// neighbours. At the renderer's 1280 x 720 the levels run 320 x 180 down to 1 x 1 through odd
// sizes (45 -> 22), where the linear filter's taps fall between texels.
TEST(CameraImage, TheCpuReductionIsTheGpuCaptureAtEveryLevel)
{
    constexpr int kFrameWidth = 1280, kFrameHeight = 720;
    LUMAR_RENDERER_OR_SKIP(renderer, kFrameWidth, kFrameHeight);
    (void)renderer;
    Image8 image(kFrameWidth, kFrameHeight, 3);
    std::mt19937 random(7);
    std::uniform_int_distribution<int> value(0, 255);
    for (uint8_t& byte : image.data)
        byte = uint8_t(value(random));
    RenderTarget target(kFrameWidth, kFrameHeight, 1);
    BackgroundPass background(target);
    target.bindForDrawing();
    background.draw(image);
    CameraImage onGpu(kFrameWidth, kFrameHeight);
    onGpu.capture(target);
    CameraImage onCpu(kFrameWidth, kFrameHeight);
    onCpu.reduce(image);
    onCpu.uploadReduced();
    const int levels = int(std::bit_width(unsigned(std::max(onGpu.width(), onGpu.height()))));
    ASSERT_EQ(levels, 9);
    for (int level = 0; level < levels; ++level) {
        const int w = std::max(1, onGpu.width() >> level), h = std::max(1, onGpu.height() >> level);
        const std::vector<uint8_t> gpu = readRgba8(onGpu.texture(), w, h, level);
        const std::vector<uint8_t> cpu = readRgba8(onCpu.texture(), w, h, level);
        int worst = 0;
        double sum = 0.0;
        for (size_t i = 0; i < gpu.size(); ++i) {
            worst = std::max(worst, std::abs(int(gpu[i]) - int(cpu[i])));
            sum += double(int(gpu[i]) - int(cpu[i]));
        }
        // llvmpipe filters unorm8 texels in fixed point and ends about a quarter of a code
        // value above the exact mean the CPU rounds; each level is filtered from the one
        // before, so that adds up (measured: worst 1 at level 0, 3 from level 3; mean 0.28 a
        // level, 1.75 at 1 x 1).
        const double mean = sum / double(gpu.size());
        EXPECT_LE(worst, std::min(1 + level, 4)) << "level " << level << " (" << w << " x " << h << ")";
        EXPECT_LE(std::abs(mean), 0.35 * (level + 1)) << "level " << level;
        RecordProperty("level" + std::to_string(level) + "_worst", worst);
        RecordProperty("level" + std::to_string(level) + "_mean_x1000", int(mean * 1000.0));
    }
}

} // namespace
} // namespace lumar
