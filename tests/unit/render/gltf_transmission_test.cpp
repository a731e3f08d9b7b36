// KHR_materials_transmission, KHR_materials_ior and KHR_materials_volume as the loader reads
// them into GltfMaterial::transmission, the `glass` preset's transmission, and every bad value
// refused in one line naming the file and the material's index.
#include <cmath>
#include <string>
#include <string_view>

#include <gtest/gtest.h>

#include "feature_gltf.h"
#include "gles_renderer/assets/gltf_model.h"
#include "gles_renderer/assets/lafortune_material.h"
#include "gles_renderer/assets/material_overrides.h"
#include "render_test_support.h"

namespace lumar {
namespace {

using test::FeatureGltf;
using test::ScratchDir;

// A one-quad model whose material is `json`.
std::filesystem::path modelWith(const ScratchDir& dir, const std::string& name, const std::string& json)
{
    FeatureGltf g;
    g.primitive(g.quadAttributes(0, 0, 1, 1, 0, 0, 0, 1, 1), g.material(R"({"name":"first"})"));
    g.primitive(g.quadAttributes(0, 0, 1, 1, 0, 0, 0, 1, 1), g.material(json));
    g.extensionsUsed = {"KHR_materials_transmission", "KHR_materials_ior", "KHR_materials_volume"};
    return g.save(dir, name);
}

TEST(GltfTransmission, FactorsTextureIorAndVolumeAreRead)
{
    ScratchDir dir;
    FeatureGltf g;
    const int texture = g.texture(dir, "t", test::texelImage(1, 1, {{{128, 0, 0, 255}}}));
    g.primitive(
        g.quadAttributes(0, 0, 1, 1, 0, 0, 0, 1, 1),
        g.material(R"({"pbrMetallicRoughness":{"baseColorFactor":[0.5,0.8,1,1]},"extensions":{)"
                   R"("KHR_materials_transmission":{"transmissionFactor":0.75,"transmissionTexture":{"index":)" +
                   std::to_string(texture) +
                   R"(,"texCoord":1}},"KHR_materials_ior":{"ior":1.33},)"
                   R"("KHR_materials_volume":{"thicknessFactor":0.2,"attenuationDistance":0.5,)"
                   R"("attenuationColor":[0.9,0.5,0.25]}}})"));
    g.primitive(g.quadAttributes(0, 0, 1, 1, 0, 0, 0, 1, 1), g.material("{}"));
    const GltfModel model = loadGltfModel(g.save(dir, "glass"));
    const GltfTransmission& t = model.materials[0].transmission;
    EXPECT_FLOAT_EQ(t.factor, 0.75f);
    ASSERT_GE(t.texture, 0);
    EXPECT_FALSE(model.textures[size_t(t.texture)].srgb) << "transmission is data, not colour";
    EXPECT_EQ(t.uvTransform.texCoord, 1);
    EXPECT_FLOAT_EQ(t.ior, 1.33f);
    EXPECT_FLOAT_EQ(t.thickness, 0.2f);
    EXPECT_FLOAT_EQ(t.attenuationDistance, 0.5f);
    EXPECT_EQ(t.attenuationColor, glm::vec3(0.9f, 0.5f, 0.25f));
    EXPECT_EQ(t.tint, glm::vec3(0.5f, 0.8f, 1.0f)) << "glTF tints the light through with the base colour";

    // Without the extensions: nothing passes, the defaults of the specifications.
    const GltfTransmission& none = model.materials[1].transmission;
    EXPECT_EQ(none.factor, 0.0f);
    EXPECT_EQ(none.texture, -1);
    EXPECT_FLOAT_EQ(none.ior, 1.5f);
    EXPECT_EQ(none.thickness, 0.0f) << "thin-walled";
    EXPECT_TRUE(std::isinf(none.attenuationDistance));
}

// KHR_materials_volume thicknessTexture: read as linear data, and its green (the
// specification's channel) scales the thickness factor where the renderer uses the thickness
// (one number per material: the mean over the texture).
TEST(GltfTransmission, TheThicknessTextureScalesTheThickness)
{
    ScratchDir dir;
    FeatureGltf g;
    // Green 255 and 51 (1 and 0.2): mean 0.6; red and blue must not count.
    const int texture = g.texture(dir, "thickness", test::texelImage(2, 1, {{0, 255, 0, 255}, {255, 51, 255, 255}}));
    g.primitive(g.quadAttributes(0, 0, 1, 1, 0, 0, 0, 1, 1),
                g.material(R"({"extensions":{"KHR_materials_transmission":{"transmissionFactor":1},)"
                           R"("KHR_materials_volume":{"thicknessFactor":0.5,"thicknessTexture":{"index":)" +
                           std::to_string(texture) + R"(}}}})"));
    g.extensionsUsed = {"KHR_materials_transmission", "KHR_materials_volume"};
    const GltfModel model = loadGltfModel(g.save(dir, "thick"));
    const GltfTransmission& t = model.materials[0].transmission;
    EXPECT_FLOAT_EQ(t.thickness, 0.5f);
    ASSERT_GE(t.thicknessTexture, 0);
    EXPECT_FALSE(model.textures[size_t(t.thicknessTexture)].srgb) << "thickness is data, not colour";
    EXPECT_NEAR(volumeThickness(t, model.textures), 0.5f * 0.6f, 1e-4f);

    // Without a texture (or with one the model does not hold) the factor alone.
    GltfTransmission plain = t;
    plain.thicknessTexture = -1;
    EXPECT_EQ(volumeThickness(plain, model.textures), 0.5f);
    plain.thicknessTexture = 9;
    EXPECT_EQ(volumeThickness(plain, model.textures), 0.5f);
}

TEST(GltfTransmission, IorZeroIsTheSpecialValue)
{
    ScratchDir dir;
    const GltfModel model = loadGltfModel(modelWith(dir, "zero", R"({"extensions":{"KHR_materials_ior":{"ior":0}}})"));
    EXPECT_EQ(model.materials[1].transmission.ior, 0.0f);
}

TEST(GltfTransmission, BadValuesNameTheFileAndTheMaterial)
{
    ScratchDir dir;
    const struct {
        const char* name;
        const char* json;
        const char* expected;
    } cases[] = {
        {"ior_low", R"({"extensions":{"KHR_materials_ior":{"ior":0.5}}})",
         "material 1 KHR_materials_ior ior: 0.5 is below 1"},
        {"ior_negative", R"({"extensions":{"KHR_materials_ior":{"ior":-1}}})", "material 1 KHR_materials_ior ior"},
        {"ior_huge", R"({"extensions":{"KHR_materials_ior":{"ior":1e300}}})", "material 1 KHR_materials_ior ior"},
        {"ior_text", R"({"extensions":{"KHR_materials_ior":{"ior":"glass"}}})", "ior: expected a number"},
        {"factor_high", R"({"extensions":{"KHR_materials_transmission":{"transmissionFactor":1.5}}})",
         "material 1 KHR_materials_transmission transmissionFactor: 1.5"},
        {"factor_huge", R"({"extensions":{"KHR_materials_transmission":{"transmissionFactor":-1e300}}})",
         "material 1 KHR_materials_transmission transmissionFactor"},
        {"texture_bad", R"({"extensions":{"KHR_materials_transmission":{"transmissionTexture":{"index":7}}}})",
         "material 1 KHR_materials_transmission transmissionTexture: texture 7 does not exist"},
        {"thickness_text", R"({"extensions":{"KHR_materials_volume":{"thicknessFactor":"thick"}}})",
         "material 1 KHR_materials_volume thicknessFactor: expected a number"},
        {"thickness", R"({"extensions":{"KHR_materials_volume":{"thicknessFactor":-0.1}}})",
         "material 1 KHR_materials_volume thicknessFactor"},
        {"distance", R"({"extensions":{"KHR_materials_volume":{"attenuationDistance":0}}})",
         "material 1 KHR_materials_volume attenuationDistance"},
        {"colour", R"({"extensions":{"KHR_materials_volume":{"attenuationColor":[1,2,0]}}})",
         "material 1 KHR_materials_volume attenuationColor"},
        {"colour_short", R"({"extensions":{"KHR_materials_volume":{"attenuationColor":[1,1]}}})",
         "material 1 KHR_materials_volume attenuationColor"},
        {"thickness_texture_bad", R"({"extensions":{"KHR_materials_volume":{"thicknessTexture":{"index":7}}}})",
         "material 1 KHR_materials_volume thicknessTexture: texture 7 does not exist"},
        {"thickness_texture_not_info", R"({"extensions":{"KHR_materials_volume":{"thicknessTexture":3}}})",
         "material 1 KHR_materials_volume thicknessTexture: expected a textureInfo object"},
        {"thickness_texture_texcoord",
         R"({"extensions":{"KHR_materials_volume":{"thicknessTexture":{"index":0,"texCoord":-1}}}})",
         "material 1 KHR_materials_volume thicknessTexture texCoord: expected a non-negative integer"},
    };
    for (const auto& c : cases) {
        SCOPED_TRACE(c.name);
        const std::filesystem::path file = modelWith(dir, c.name, c.json);
        const std::string message = test::expectInputErrorNamingFile([&] { (void)loadGltfModel(file); }, file);
        EXPECT_NE(message.find(c.expected), std::string::npos) << message;
    }
}

TEST(GltfTransmission, TheGlassPresetLetsLightThroughAndOthersDoNot)
{
    const GltfTransmission glass = materialPresetTransmission("glass");
    EXPECT_EQ(glass.factor, 1.0f);
    EXPECT_FLOAT_EQ(glass.ior, 1.5f);
    EXPECT_GT(glass.thickness, 0.0f) << "solid: the view bends at its surface";
    EXPECT_EQ(glass.tint, glm::vec3(1.0f)) << "clear";
    const GltfTransmission pane = materialPresetTransmission("thin_glass");
    EXPECT_EQ(pane.factor, 1.0f);
    EXPECT_FLOAT_EQ(pane.ior, 1.5f);
    EXPECT_EQ(pane.thickness, 0.0f) << "thin-walled: the view passes straight through";
    EXPECT_EQ(pane.tint, glm::vec3(1.0f)) << "clear";
    for (const std::string_view name : materialPresetNames()) {
        if (name != "glass" && name != "thin_glass") {
            EXPECT_EQ(materialPresetTransmission(name).factor, 0.0f) << name;
        }
    }

    // Applied, the preset replaces what the file said: glass turns transmissive, chrome not.
    ScratchDir dir;
    GltfModel model = loadGltfModel(modelWith(
        dir, "preset", R"({"name":"window","extensions":{"KHR_materials_transmission":{"transmissionFactor":1}}})"));
    MaterialOverrides overrides;
    overrides.materials["first"].preset = "glass";
    overrides.materials["window"].preset = "chrome";
    applyMaterialOverrides(model, overrides);
    EXPECT_EQ(model.materials[0].transmission.factor, 1.0f);
    EXPECT_EQ(model.materials[1].transmission.factor, 0.0f);
}

} // namespace
} // namespace lumar
