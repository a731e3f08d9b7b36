// Emission feeds the lens effects (issue 17, deliverable 4), measured on Khronos'
// EmissiveStrengthTest (../shared/data/models): five cubes with the same emissiveFactor
// (0.1, 0.5, 0.9) and KHR_materials_emissive_strength 1, 2, 4, 8 and 16 in a row before a
// backdrop. Rendered with the bloom on and off, the light the bloom adds around each cube (the
// frame's code values with it minus without it, outside the cube's own pixels) is none for
// strength 1 (0.9 < the threshold 1) and grows with the strength (each doubling by 30 % or more),
// and so does the distance it reaches; in both image formats (RGBA16F and RGBM).
#include <algorithm>
#include <array>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "gl_test_support.h"
#include "gles_renderer/assets/gltf_model.h"

namespace lumar {
namespace {

constexpr int kW = 640, kH = 240;
constexpr double kDistance = 16.0; // metres from the camera to the cubes' centres
constexpr double kFocal = 600.0;
constexpr std::array<double, 5> kCubeX = {-6.0, -3.0, 0.0, 3.0, 6.0}; // strengths 1, 2, 4, 8, 16

struct CubeBloom {
    double energy = 0.0; // sum of the added code values (all channels) around the cube
    int reach = 0;       // pixels beyond the cube's box where a channel still gains > 2
};

// The cubes' box in pixels: the front face (0.5 m nearer) covers the most.
struct PixelBox {
    int x0, y0, x1, y1;
};

PixelBox cubeBox(double x)
{
    const double z = kDistance - 0.5;
    const auto px = [&](double v) { return kW / 2.0 + kFocal * v / z; };
    const auto py = [&](double v) { return kH / 2.0 + kFocal * v / z; };
    return {int(px(x - 0.5)) - 2, int(py(-0.5)) - 2, int(px(x + 0.5)) + 2, int(py(0.5)) + 2};
}

std::array<CubeBloom, kCubeX.size()> measureBloom(const Image8& on, const Image8& off)
{
    std::array<CubeBloom, kCubeX.size()> blooms{};
    for (size_t i = 0; i < kCubeX.size(); ++i) {
        const PixelBox box = cubeBox(kCubeX[i]);
        // Half way to the neighbours (the cubes are 3 m apart, ~110 px).
        const int half = int(kFocal * 1.5 / kDistance) - 2;
        const int cx = (box.x0 + box.x1) / 2, cy = (box.y0 + box.y1) / 2;
        for (int y = std::max(0, cy - half); y < std::min(kH, cy + half); ++y)
            for (int x = std::max(0, cx - half); x < std::min(kW, cx + half); ++x) {
                if (x >= box.x0 && x <= box.x1 && y >= box.y0 && y <= box.y1)
                    continue;
                int gain = 0;
                for (int c = 0; c < 3; ++c)
                    gain = std::max(gain, int(on.at(x, y)[c]) - int(off.at(x, y)[c]));
                for (int c = 0; c < 3; ++c)
                    blooms[i].energy += std::max(0, int(on.at(x, y)[c]) - int(off.at(x, y)[c]));
                if (gain > 2) {
                    const int dx = std::max({box.x0 - x, x - box.x1, 0}), dy = std::max({box.y0 - y, y - box.y1, 0});
                    blooms[i].reach = std::max(blooms[i].reach, std::max(dx, dy));
                }
            }
    }
    return blooms;
}

TEST(EmissionBloom, StrongerEmissiveStrengthBloomsMoreAndFurther)
{
    const std::filesystem::path file = std::filesystem::path(LUMAR_SHARED_DATA_DIR) / "models/EmissiveStrengthTest.glb";
    if (!std::filesystem::exists(file))
        GTEST_SKIP() << file << " is absent (../shared/data exists on development machines only)";
    const GltfModel model = loadGltfModel(file);
    // glTF's +y up and +z towards the viewer to the OpenCV camera's y down and z forward.
    glm::dmat4 cameraFromModel = test::translation(0.0, 0.0, kDistance);
    cameraFromModel[1][1] = -1.0;
    cameraFromModel[2][2] = -1.0;
    const CameraIntrinsics k = test::makeIntrinsics(kW, kH, kFocal, kFocal, kW / 2.0, kH / 2.0);
    const Image8 grey = test::solidImage(kW, kH, 40, 40, 40);

    for (const bool rgbm : {false, true}) {
        SCOPED_TRACE(rgbm ? "rgbm" : "float");
        const auto render = [&](bool lensOn) {
            RenderOptions options;
            options.environmentMaps.ibl.forceRgbm = rgbm;
            options.lens.enabled = lensOn;
            options.lens.images = rgbm ? LensImageFormat::Rgbm : LensImageFormat::Float;
            options.lens.threshold = 1.0f;
            options.lens.bloomIntensity = 0.5f;
            options.lens.bloomRadius = 16.0f;
            options.lens.glare = false;
            auto made = test::tryCreateRenderer(kW, kH, options);
            Image8 out;
            if (!made.renderer)
                return out;
            made.renderer->setEnvironment(test::uniformEnvironment(0.2f), 1.0f);
            const DrawItem item{made.renderer->addModel(model), cameraFromModel};
            made.renderer->render(grey, k, {&item, 1});
            made.renderer->readback(out);
            return out;
        };
        const Image8 off = render(false);
        if (off.width == 0)
            GTEST_SKIP() << "no GLES 3 renderer";
        const Image8 on = render(true);
        for (size_t i = 0; i < on.data.size(); ++i)
            ASSERT_GE(int(on.data[i]), int(off.data[i]) - 1) << "the bloom only adds light";

        const auto blooms = measureBloom(on, off);
        for (size_t i = 0; i < blooms.size(); ++i)
            std::printf("strength %d: bloom energy %.0f, reach %d px\n", 1 << i, blooms[i].energy, blooms[i].reach);
        // Strength 1: every channel (at most 0.9) below the threshold, nothing added.
        EXPECT_LE(blooms[0].energy, 0.01 * blooms[1].energy);
        EXPECT_EQ(blooms[0].reach, 0);
        for (size_t i = 1; i < blooms.size(); ++i) {
            SCOPED_TRACE("strength " + std::to_string(1 << i));
            // Each doubling adds light above the threshold: at least 30 % more bloom.
            EXPECT_GT(blooms[i].energy, 1.3 * blooms[i - 1].energy);
            // The reach steps with the pyramid's texels: equal within 2 px from one to the next.
            EXPECT_GE(blooms[i].reach, blooms[i - 1].reach - 2);
        }
        EXPECT_GE(blooms[4].reach, blooms[1].reach + 5); // 16 x reaches 5 px or more further than 2 x
    }
}

// A BLEND surface before a bright emitter, with the lens effects on. Float images blend the
// radiance like the frame (the red surface adds its light to the bloom). RGBM images cannot
// (alpha is the encoding's scale), so the radiance is left out while BLEND primitives are
// blended (LensEffects::blendingVirtual): the emitter's bloom around it stays as it is without
// the surface, where blending the encoding weighed the colours by the scale (the white bloom
// turned red: a quarter of its green left here).
TEST(EmissionBloom, BlendSurfaceKeepsTheRgbmRadianceBehindIt)
{
    constexpr int w = 160, h = 120;
    const CameraIntrinsics k = test::makeIntrinsics(w, h, 200.0, 200.0, w / 2.0, h / 2.0);
    const GltfModel emitter = test::cameraFacingRectangle(-0.1f, -0.1f, 0.1f, 0.1f, test::emissiveMaterial({8, 8, 8}));
    GltfMaterial red = test::emissiveMaterial({12, 0, 0});
    red.baseColorFactor.a = 0.5f;
    red.alphaMode = GltfAlphaMode::Blend;
    // Nearer, covering the emitter's pixels exactly (0.075 m at 1.5 m is 0.1 m at 2 m).
    const GltfModel surface = test::cameraFacingRectangle(-0.075f, -0.075f, 0.075f, 0.075f, red);
    const Image8 grey = test::solidImage(w, h, 40, 40, 40);
    for (const bool rgbm : {false, true}) {
        SCOPED_TRACE(rgbm ? "rgbm" : "float");
        const auto render = [&](bool withSurface) {
            RenderOptions options;
            options.environmentMaps.ibl.forceRgbm = rgbm;
            options.lens.enabled = true;
            options.lens.images = rgbm ? LensImageFormat::Rgbm : LensImageFormat::Float;
            options.lens.threshold = 1.0f;
            options.lens.bloomIntensity = 0.5f;
            options.lens.bloomRadius = 16.0f;
            options.lens.glare = false;
            auto made = test::tryCreateRenderer(w, h, options);
            Image8 out;
            if (!made.renderer)
                return out;
            made.renderer->setEnvironment(test::uniformEnvironment(0.0f), 1.0f);
            std::vector<DrawItem> items{{made.renderer->addModel(emitter), test::translation(0, 0, 2)}};
            if (withSurface)
                items.push_back({made.renderer->addModel(surface), test::translation(0, 0, 1.5)});
            made.renderer->render(grey, k, items);
            made.renderer->readback(out);
            return out;
        };
        const Image8 bare = render(false);
        if (bare.width == 0)
            GTEST_SKIP() << "no GLES 3 renderer";
        const Image8 covered = render(true);
        // The bloom's ring beyond the emitter's pixels (x in [70, 90), y in [50, 70), 3 px more).
        glm::dvec3 bareRing(0.0), coveredRing(0.0);
        for (int y = 0; y < h; ++y)
            for (int x = 0; x < w; ++x) {
                if (x >= 67 && x < 93 && y >= 47 && y < 73)
                    continue;
                for (int c = 0; c < 3; ++c) {
                    bareRing[c] += std::max(0, int(bare.at(x, y)[c]) - 40);
                    coveredRing[c] += std::max(0, int(covered.at(x, y)[c]) - 40);
                }
            }
        std::printf("%s: ring gain without the surface (%.0f, %.0f, %.0f), with it (%.0f, %.0f, %.0f)\n",
                    rgbm ? "rgbm" : "float", bareRing.r, bareRing.g, bareRing.b, coveredRing.r, coveredRing.g,
                    coveredRing.b);
        ASSERT_GT(bareRing.g, 1000.0) << "the emitter blooms";
        if (rgbm) {
            for (int c = 0; c < 3; ++c)
                EXPECT_NEAR(coveredRing[c], bareRing[c], 0.05 * bareRing[c]) << "channel " << c;
        } else {
            EXPECT_GT(coveredRing.r, 1.1 * bareRing.r) << "the red surface's light blooms";
            EXPECT_LT(coveredRing.g, 0.8 * bareRing.g) << "and dims the emitter's";
        }
    }
}

} // namespace
} // namespace lumar
