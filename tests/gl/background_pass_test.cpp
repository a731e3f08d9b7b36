// A pixel no model touches comes out of the renderer exactly as the camera delivered it.
#include <random>

#include <gtest/gtest.h>

#include "gl_test_support.h"

namespace lumar {
namespace {

Image8 randomImage(int width, int height, unsigned seed)
{
    std::mt19937 random(seed);
    std::uniform_int_distribution<int> byte(0, 255);
    Image8 image(width, height, 3);
    for (uint8_t& v : image.data)
        v = uint8_t(byte(random));
    return image;
}

void expectBitExactCopy(SceneRenderer& renderer, unsigned seed)
{
    const Image8 camera = randomImage(renderer.width(), renderer.height(), seed);
    const CameraIntrinsics k = defaultIntrinsics(renderer.width(), renderer.height());
    Image8 out;
    renderer.render(camera, k, {});
    renderer.readback(out);
    ASSERT_EQ(out.width, camera.width);
    ASSERT_EQ(out.height, camera.height);
    ASSERT_EQ(out.channels, 3);
    size_t differing = 0;
    for (size_t i = 0; i < out.data.size(); ++i)
        differing += out.data[i] != camera.data[i];
    EXPECT_EQ(differing, 0u) << "of " << out.data.size() << " bytes";
}

// An odd width makes rows that are not 4-byte aligned (the unpack/pack alignment trap).
TEST(BackgroundPass, CopiesARandomCameraImageBitExactly)
{
    LUMAR_RENDERER_OR_SKIP(renderer, 317, 203);
    expectBitExactCopy(renderer, 1);
    expectBitExactCopy(renderer, 2); // the persistent texture is updated, not stale
}

TEST(BackgroundPass, CopiesBitExactlyWithMultisampling)
{
    RenderOptions options;
    options.samples = 4;
    LUMAR_RENDERER_OR_SKIP(renderer, 160, 90, options);
    expectBitExactCopy(renderer, 3);
}

TEST(BackgroundPass, PixelsAroundAModelAreUnchanged)
{
    LUMAR_RENDERER_OR_SKIP(renderer, 200, 150);
    const CameraIntrinsics k = test::makeIntrinsics(200, 150, 180, 180, 99.5, 74.5);
    const ModelId quad =
        renderer.addModel(test::cameraFacingRectangle(-0.1f, -0.1f, 0.1f, 0.1f, test::emissiveMaterial({1, 1, 1})));
    const Image8 camera = randomImage(200, 150, 4);
    const DrawItem item{quad, test::translation(0, 0, 1)};
    Image8 out;
    renderer.render(camera, k, {&item, 1});
    renderer.readback(out);
    // The quad projects to [81.5, 117.5] x [56.5, 92.5]; leave a pixel of margin.
    size_t differing = 0, checked = 0;
    for (int y = 0; y < 150; ++y)
        for (int x = 0; x < 200; ++x) {
            if (x >= 80 && x <= 119 && y >= 55 && y <= 94)
                continue;
            ++checked;
            for (int c = 0; c < 3; ++c)
                differing += out.at(x, y)[c] != camera.at(x, y)[c];
        }
    EXPECT_EQ(differing, 0u) << "of " << checked << " pixels";
    // And the quad was drawn: emission 1 plus the 4% dielectric lobe (rho_s = 0.04, no
    // Fresnel gain facing the camera) of the default uniform environment of radiance 1.
    const int expected = test::toneMappedCode(1.0 + 0.04);
    for (int c = 0; c < 3; ++c)
        EXPECT_NEAR(out.at(99, 74)[c], expected, 2);
}

} // namespace
} // namespace lumar
