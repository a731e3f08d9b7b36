// The metallic-roughness to Lafortune conversion against hand-computed values, the Fresnel
// factor with phi = 1/6 against Schlick's formula, the presets' physical bounds, and the swirl
// rotation texture against the circle tangent at every texel; the emissive preset's light.
#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>

#include <gtest/gtest.h>

#include "core/error.h"
#include "gles_renderer/assets/builtin_shapes.h"
#include "gles_renderer/assets/lafortune_material.h"
#include "gles_renderer/assets/material_overrides.h"

namespace lumar {
namespace {

void expectVec3Near(const glm::vec3& actual, const glm::vec3& expected, float tolerance)
{
    for (int i = 0; i < 3; ++i) {
        EXPECT_NEAR(actual[i], expected[i], tolerance) << "component " << i;
    }
}

TEST(LafortuneMaterial, MetallicRoughnessGrid)
{
    const glm::vec3 base(0.8f, 0.5f, 0.2f);
    struct Row {
        float roughness;
        float exponent; // 2/alpha^2 - 2, alpha = roughness^2, clamped to [1, 4096]
    };
    // roughness 0: alpha 0, n infinite -> the cap; 0.5: alpha 0.25, 2/0.0625 - 2 = 30;
    // 1: alpha 1, 2 - 2 = 0 -> the floor 1.
    const Row rows[] = {{0.0f, 4096.0f}, {0.5f, 30.0f}, {1.0f, 1.0f}};
    for (const Row& row : rows) {
        for (const float metallic : {0.0f, 1.0f}) {
            SCOPED_TRACE("roughness " + std::to_string(row.roughness) + " metallic " + std::to_string(metallic));
            const LafortuneParams p = lafortuneFromMetallicRoughness(base, metallic, row.roughness);
            EXPECT_NEAR(p.exponent, row.exponent, row.exponent * 1e-6f);
            expectVec3Near(p.diffuse, metallic == 0.0f ? base : glm::vec3(0.0f), 1e-7f);
            expectVec3Near(p.specular, metallic == 0.0f ? glm::vec3(0.04f) : base, 1e-7f);
            expectVec3Near(p.lobe, glm::vec3(-1.0f, -1.0f, 1.0f), 0.0f);
            EXPECT_FLOAT_EQ(p.fresnelPhi, 1.0f / 6.0f);
            EXPECT_EQ(p.tangentRotation, 0.0f);
        }
    }
}

TEST(LafortuneMaterial, IntermediateValuesAndClamping)
{
    const glm::vec3 base(0.8f, 0.5f, 0.2f);
    // roughness 0.3: alpha 0.09, alpha^2 0.0081, n = 2/0.0081 - 2 = 244.9136
    const LafortuneParams p = lafortuneFromMetallicRoughness(base, 0.5f, 0.3f);
    EXPECT_NEAR(p.exponent, 2.0 / 0.0081 - 2.0, 0.01);
    expectVec3Near(p.diffuse, base * 0.5f, 1e-6f);
    expectVec3Near(p.specular, 0.5f * glm::vec3(0.04f) + 0.5f * base, 1e-6f);

    // n = 2/roughness^4 - 2 reaches the cap at roughness (2/4098)^(1/4) = 0.14864; just above
    // it n is below but close to 4096 (no jump), just below it is exactly the cap.
    const float knee = float(std::pow(2.0 / 4098.0, 0.25));
    EXPECT_NEAR(lafortuneFromMetallicRoughness(base, 0.0f, knee * 1.001f).exponent, 4098.0 / std::pow(1.001, 4.0) - 2.0,
                1.0);
    EXPECT_EQ(lafortuneFromMetallicRoughness(base, 0.0f, knee * 0.999f).exponent, kMaxLafortuneExponent);

    // Out-of-range inputs are clamped rather than producing NaN or negative exponents.
    const LafortuneParams clamped = lafortuneFromMetallicRoughness(glm::vec3(2.0f, -1.0f, 0.5f), 1.5f, -0.2f);
    EXPECT_EQ(clamped.exponent, kMaxLafortuneExponent);
    expectVec3Near(clamped.specular, glm::vec3(1.0f, 0.0f, 0.5f), 1e-7f);
    expectVec3Near(clamped.diffuse, glm::vec3(0.0f), 1e-7f);
    EXPECT_EQ(lafortuneFromMetallicRoughness(base, 0.0f, 3.0f).exponent, kMinLafortuneExponent);
}

// The paper's factor f(R) = (1 - R.N)^(1/phi - 1) with phi = 1/6 makes rho_s + (1 - rho_s) f
// Schlick's F0 + (1 - F0)(1 - cos)^5.
TEST(LafortuneMaterial, FresnelPhiOneSixthIsSchlick)
{
    EXPECT_FLOAT_EQ(kMetallicRoughnessFresnelPhi, 1.0f / 6.0f);
    double worst = 0.0;
    for (const double f0 : {double(kDielectricSpecular), 0.5, 0.95}) {
        for (int i = 0; i <= 1000; ++i) {
            const double cosTheta = i / 1000.0;
            const float phi = kMetallicRoughnessFresnelPhi;
            const double paper = std::pow(1.0 - cosTheta, 1.0 / double(phi) - 1.0);
            const double m = 1.0 - cosTheta;
            const double schlick = f0 + (1.0 - f0) * m * m * m * m * m;
            worst = std::max(worst, std::abs((f0 + (1.0 - f0) * paper) - schlick));
        }
    }
    // phi is a float: 1/phi - 1 = 4.99999982, which moves the factor by at most 1.3e-8.
    EXPECT_LT(worst, 1e-7);
}

TEST(LafortuneMaterial, PresetsArePhysicallyPlausible)
{
    const auto names = materialPresetNames();
    ASSERT_GE(names.size(), 7u);
    for (const char* required : {"chrome", "brushed_metal", "car_paint", "rubber", "plastic", "glass", "emissive"}) {
        EXPECT_NE(std::find(names.begin(), names.end(), std::string_view(required)), names.end()) << required;
    }
    for (const std::string_view name : names) {
        SCOPED_TRACE(std::string(name));
        const std::optional<LafortuneParams> p = materialPreset(name);
        ASSERT_TRUE(p.has_value());
        for (int c = 0; c < 3; ++c) {
            EXPECT_GE(p->diffuse[c], 0.0f);
            EXPECT_GE(p->specular[c], 0.0f);
            EXPECT_LE(p->diffuse[c] + p->specular[c], 1.0f); // energy: reflects no more than it receives
            EXPECT_LE(std::abs(p->lobe[c]), 1.0f);           // lobe magnitude <= 1
        }
        EXPECT_GT(glm::length(p->lobe), 0.0f);
        EXPECT_GE(p->exponent, kMinLafortuneExponent);
        EXPECT_LE(p->exponent, kMaxLafortuneExponent);
        EXPECT_GE(p->fresnelPhi, 0.0f);
        EXPECT_LT(p->fresnelPhi, 1.0f);
        EXPECT_GE(p->tangentRotation, 0.0f);
        EXPECT_LE(p->tangentRotation, 1.0f);
    }
    EXPECT_FALSE(materialPreset("gold").has_value());
    EXPECT_FALSE(materialPreset("").has_value());

    const LafortuneParams chrome = *materialPreset("chrome");
    expectVec3Near(chrome.diffuse, glm::vec3(0.0f), 0.0f);
    expectVec3Near(chrome.specular, glm::vec3(0.95f), 0.01f);
    EXPECT_EQ(chrome.exponent, 4096.0f);
    EXPECT_NEAR(chrome.fresnelPhi, 0.17f, 0.01f);

    const LafortuneParams brushed = *materialPreset("brushed_metal");
    EXPECT_GT(std::abs(std::abs(brushed.lobe.x) - std::abs(brushed.lobe.y)), 0.1f);
    EXPECT_NEAR(brushed.exponent, 200.0f, 50.0f);
    expectVec3Near(brushed.diffuse, glm::vec3(0.0f), 0.0f);
    EXPECT_TRUE(materialPresetUsesSwirlRotation("brushed_metal"));
    EXPECT_FALSE(materialPresetUsesSwirlRotation("chrome"));
    EXPECT_FALSE(materialPresetUsesSwirlRotation("gold"));

    const LafortuneParams paint = *materialPreset("car_paint");
    EXPECT_GT(paint.diffuse.r, 5.0f * paint.diffuse.g);     // coloured base
    EXPECT_NEAR(paint.specular.r, paint.specular.b, 1e-6f); // clear (neutral) coat
    EXPECT_NEAR(paint.exponent, 500.0f, 100.0f);
    EXPECT_NEAR(paint.fresnelPhi, 0.2f, 0.02f);

    const LafortuneParams rubber = *materialPreset("rubber");
    EXPECT_LT(rubber.diffuse.r, 0.1f);
    EXPECT_LT(rubber.specular.r, 0.1f);
    EXPECT_NEAR(rubber.exponent, 4.0f, 2.0f);

    const LafortuneParams plastic = *materialPreset("plastic");
    EXPECT_NEAR(plastic.exponent, 60.0f, 10.0f);
    expectVec3Near(plastic.specular, glm::vec3(0.05f), 1e-6f);

    const LafortuneParams glass = *materialPreset("glass");
    expectVec3Near(glass.diffuse, glm::vec3(0.0f), 0.0f);
    expectVec3Near(glass.specular, glm::vec3(0.04f), 1e-6f);
    EXPECT_EQ(glass.exponent, 4096.0f);
    EXPECT_NEAR(glass.fresnelPhi, 0.17f, 0.01f);
}

TEST(LafortuneMaterial, SwirlTextureAtKnownTexels)
{
    const Image8 swirl = makeSwirlRotationTexture(256);
    ASSERT_EQ(swirl.width, 256);
    ASSERT_EQ(swirl.height, 256);
    ASSERT_EQ(swirl.channels, 4);
    // Centre c = 128; texel (col, row) at x = col + 0.5 - 128, y = 128 - (row + 0.5) (up).
    struct Known {
        int col, row;
        int value; // round(255 * angle/pi)
    };
    const Known known[] = {
        {255, 127, 128}, // right of the centre: x 127.5, y 0.5, tangent vertical, a = 0.50125
        {128, 0, 255},   // above it: x 0.5, y 127.5, tangent horizontal (a = 0.99875, i.e. ~pi)
        {255, 0, 191},   // top-right: position 45 degrees, tangent 135 degrees, a = 0.75
        {0, 0, 64},      // top-left: position 135, tangent 225 = 45 mod 180, a = 0.25
        {255, 255, 64},  // bottom-right: position -45, tangent 45
        {0, 255, 191},   // bottom-left: position -135, tangent -45 = 135 mod 180
    };
    for (const Known& k : known) {
        const uint8_t* texel = swirl.at(k.col, k.row);
        EXPECT_EQ(int(texel[0]), k.value) << "texel " << k.col << "," << k.row;
    }

    // Every texel: g = b = r, opaque, and the decoded direction (cos, sin)(a pi) (in the
    // frame x = T, y = B) is perpendicular to the radius up to the 8-bit quantisation
    // (half a step of pi/255).
    const double tolerance = std::sin(std::numbers::pi / 510.0) + 1e-9;
    double worst = 0.0;
    for (int row = 0; row < 256; ++row) {
        for (int col = 0; col < 256; ++col) {
            const uint8_t* texel = swirl.at(col, row);
            ASSERT_EQ(texel[1], texel[0]);
            ASSERT_EQ(texel[2], texel[0]);
            ASSERT_EQ(texel[3], 255);
            const double angle = texel[0] / 255.0 * std::numbers::pi;
            const double x = col + 0.5 - 128.0, y = 128.0 - (row + 0.5);
            worst = std::max(worst, std::abs(std::cos(angle) * x + std::sin(angle) * y) / std::hypot(x, y));
        }
    }
    EXPECT_LE(worst, tolerance);
    EXPECT_GT(worst, tolerance * 0.5); // the quantisation is visible, so the check is not vacuous

    EXPECT_THROW(makeSwirlRotationTexture(0), InputError);
    EXPECT_THROW(makeSwirlRotationTexture(20000), InputError);
    EXPECT_EQ(makeSwirlRotationTexture(1).at(0, 0)[0], 128); // the centre itself: atan2(0, 0) = 0
}

// The emissive preset lights a material that emits nothing of its own with
// kEmissivePresetRadiance (above the lens's default threshold of 1, so it blooms); one that
// emits (glTF emissiveFactor x strength, here 8) keeps its light; other presets add none.
TEST(LafortuneMaterial, EmissivePresetLightsWhatDoesNotEmit)
{
    EXPECT_GT(kEmissivePresetRadiance, 1.0f);
    expectVec3Near(materialPresetEmission("emissive"), glm::vec3(kEmissivePresetRadiance), 0.0f);
    expectVec3Near(materialPresetEmission("chrome"), glm::vec3(0.0f), 0.0f);
    expectVec3Near(materialPresetEmission("gold"), glm::vec3(0.0f), 0.0f);

    const auto withPreset = [](GltfModel model, const char* preset) {
        MaterialOverrides overrides;
        overrides.materials["*"].preset = preset;
        applyMaterialOverrides(model, overrides);
        return model.materials.at(0).emissiveFactor;
    };
    expectVec3Near(withPreset(makeBuiltinShape("cube"), "emissive"), glm::vec3(kEmissivePresetRadiance), 0.0f);
    expectVec3Near(withPreset(makeBuiltinShape("cube"), "chrome"), glm::vec3(0.0f), 0.0f);
    GltfModel lamp = makeBuiltinShape("sphere");
    lamp.materials.at(0).emissiveFactor = glm::vec3(8.0f, 7.5f, 6.0f);
    expectVec3Near(withPreset(lamp, "emissive"), glm::vec3(8.0f, 7.5f, 6.0f), 0.0f);
}

} // namespace
} // namespace lumar
