// Material textures capped on upload (RenderOptions::materialTextureLimit): a texture larger
// than the limit is stored scaled down to fit, and what the renderer draws with it stays
// within a small tolerance of the full-size texture's picture.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>

#include <GLES3/gl31.h>
#include <glm/gtc/matrix_transform.hpp>
#include <gtest/gtest.h>

#include "gl_test_support.h"
#include "gles_renderer/gl/gpu_texture.h"

namespace lumar {
namespace {

TEST(MaterialTexture, CappedSizeKeepsTheAspectRatio)
{
    EXPECT_EQ(cappedTextureSize(2048, 2048, 1024), std::pair(1024, 1024));
    EXPECT_EQ(cappedTextureSize(2048, 512, 1024), std::pair(1024, 256));
    EXPECT_EQ(cappedTextureSize(300, 4096, 1024), std::pair(75, 1024));
    EXPECT_EQ(cappedTextureSize(4096, 1, 1024), std::pair(1024, 1)) << "a side never reaches 0";
    EXPECT_EQ(cappedTextureSize(1000, 1024, 1024), std::pair(1000, 1024)) << "within the limit: unchanged";
    EXPECT_EQ(cappedTextureSize(2048, 2048, 0), std::pair(2048, 2048)) << "0: no limit";
}

TEST(MaterialTexture, DownscalingKeepsAFlatColourAndAveragesAPattern)
{
    // A flat colour stays that colour; a one-texel checker of black and white becomes the
    // average in linear light (sRGB 188), not in code values (128).
    Image8 flat(64, 32, 4);
    Image8 checker(64, 32, 4);
    for (int y = 0; y < 32; ++y)
        for (int x = 0; x < 64; ++x) {
            uint8_t* f = flat.at(x, y);
            f[0] = 200, f[1] = 100, f[2] = 30, f[3] = 255;
            uint8_t* c = checker.at(x, y);
            c[0] = c[1] = c[2] = ((x + y) & 1) ? 255 : 0;
            c[3] = 255;
        }
    const Image8 smallFlat = downscaleTexture(flat, 16, 8, true);
    const Image8 smallChecker = downscaleTexture(checker, 16, 8, true);
    const Image8 linearChecker = downscaleTexture(checker, 16, 8, false);
    for (int y = 0; y < 8; ++y)
        for (int x = 0; x < 16; ++x) {
            EXPECT_NEAR(smallFlat.at(x, y)[0], 200, 1);
            EXPECT_NEAR(smallFlat.at(x, y)[1], 100, 1);
            EXPECT_NEAR(smallFlat.at(x, y)[2], 30, 1);
            EXPECT_EQ(smallFlat.at(x, y)[3], 255);
            EXPECT_NEAR(smallChecker.at(x, y)[1], 188, 3);
            EXPECT_NEAR(linearChecker.at(x, y)[1], 128, 3);
        }
}

TEST(MaterialTexture, ALargeTextureIsStoredAtTheLimit)
{
    LUMAR_RENDERER_OR_SKIP(renderer, 64, 64); // for its current context
    (void)renderer;
    Image8 image(2048, 2048, 4);
    std::fill(image.data.begin(), image.data.end(), uint8_t(90));
    const GlTexture capped = uploadMaterialTexture(image, true, 1024);
    GLint width = 0, height = 0, levels = 0;
    glBindTexture(GL_TEXTURE_2D, capped.name());
    glGetTexLevelParameteriv(GL_TEXTURE_2D, 0, GL_TEXTURE_WIDTH, &width);
    glGetTexLevelParameteriv(GL_TEXTURE_2D, 0, GL_TEXTURE_HEIGHT, &height);
    glGetTexParameteriv(GL_TEXTURE_2D, GL_TEXTURE_IMMUTABLE_LEVELS, &levels);
    EXPECT_EQ(width, 1024);
    EXPECT_EQ(height, 1024);
    EXPECT_EQ(levels, mipLevelCount(1024, 1024));
    const GlTexture full = uploadMaterialTexture(image, true);
    glBindTexture(GL_TEXTURE_2D, full.name());
    glGetTexLevelParameteriv(GL_TEXTURE_2D, 0, GL_TEXTURE_WIDTH, &width);
    EXPECT_EQ(width, 2048) << "no limit: as loaded";
    EXPECT_EQ(glGetError(), GLenum(GL_NO_ERROR));
}

// The milk truck (a 2048² base colour texture) at 1280x720 as milk_truck_test.cpp shows it
// (about 113,000 pixels), drawn with the texture as loaded and capped at 1024². Measured: 0.07%
// of its pixels more than 16 code values off, 0.22 on average; from 5 m (440,000 pixels),
// where the texture is magnified, 1% and 0.66.
Image8 renderTruck(int textureLimit, std::string& skipReason)
{
    constexpr int kWidth = 1280, kHeight = 720;
    const GltfModel truck =
        loadGltfModel(std::filesystem::path(LUMAR_SOURCE_DIR) / "daemon/assets/models/CesiumMilkTruck.glb");
    RenderOptions options;
    options.materialTextureLimit = textureLimit;
    test::RendererOrReason made = test::tryCreateRenderer(kWidth, kHeight, options);
    if (!made.renderer) {
        skipReason = made.reason;
        return {};
    }
    SceneRenderer& renderer = *made.renderer;
    renderer.setEnvironment(test::uniformEnvironment(0.8f), 1.0f);
    const ModelId id = renderer.addModel(truck);
    const glm::dvec3 centre = glm::dvec3(truck.boundsMin + truck.boundsMax) * 0.5;
    glm::dmat4 cameraFromModel = test::translation(0, 0, 9);
    cameraFromModel = glm::rotate(cameraFromModel, glm::radians(180.0), glm::dvec3(1, 0, 0));
    cameraFromModel = glm::rotate(cameraFromModel, glm::radians(35.0), glm::dvec3(0, 1, 0));
    cameraFromModel = glm::translate(cameraFromModel, -centre);
    const DrawItem item{id, cameraFromModel};
    Image8 out;
    renderer.render(test::solidImage(kWidth, kHeight, 10, 20, 30), defaultIntrinsics(kWidth, kHeight), {&item, 1});
    renderer.readback(out);
    return out;
}

TEST(MaterialTexture, TheCappedTruckLooksLikeTheFullSizeOne)
{
    std::string reason;
    const Image8 full = renderTruck(0, reason);
    if (full.data.empty())
        GTEST_SKIP() << "no GLES 3 renderer: " << reason;
    const Image8 capped = renderTruck(1024, reason);
    ASSERT_EQ(capped.data.size(), full.data.size());
    double sum = 0.0;
    size_t changed = 0, far = 0, truckPixels = 0;
    for (size_t i = 0; i < full.data.size(); i += 3) {
        const bool truck = full.data[i] != 10 || full.data[i + 1] != 20 || full.data[i + 2] != 30;
        truckPixels += truck ? 1 : 0;
        int worst = 0;
        for (size_t c = 0; c < 3; ++c) {
            const int d = std::abs(int(full.data[i + c]) - int(capped.data[i + c]));
            sum += d;
            worst = std::max(worst, d);
        }
        changed += worst > 0 ? 1 : 0;
        far += worst > 16 ? 1 : 0;
    }
    ASSERT_GT(truckPixels, 50000u) << "the truck fills a good part of the frame";
    const double meanOverTruck = sum / (3.0 * double(truckPixels));
    std::printf("capped truck: %zu of %zu truck pixels differ, %zu by more than 16; mean difference %.3f\n", changed,
                truckPixels, far, meanOverTruck);
    EXPECT_LT(meanOverTruck, 1.0);
    EXPECT_LT(double(far), 0.005 * double(truckPixels));
}

} // namespace
} // namespace lumar
