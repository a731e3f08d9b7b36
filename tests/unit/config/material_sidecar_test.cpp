// The material sidecar TOML: parsing (presets, overrides, textures), applying it to a model
// (named entries, the "*" entry, the bases fields override, the textures it appends), and
// every malformed input rejected with "FILE:LINE:" at the offending line.
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "config/material_sidecar.h"
#include "gles_renderer/assets/lafortune_material.h"
#include "unit/render/render_test_support.h"

namespace lumar {
namespace {

using test::ScratchDir;

// A 2x2 8-bit greyscale PNG: rows (0, 64) and (128, 255).
const std::vector<uint8_t> kGreyPng = {
    0x89, 0x50, 0x4e, 0x47, 0x0d, 0x0a, 0x1a, 0x0a, 0x00, 0x00, 0x00, 0x0d, 0x49, 0x48, 0x44, 0x52, 0x00, 0x00,
    0x00, 0x02, 0x00, 0x00, 0x00, 0x02, 0x08, 0x00, 0x00, 0x00, 0x00, 0x57, 0xdd, 0x52, 0xf8, 0x00, 0x00, 0x00,
    0x0e, 0x49, 0x44, 0x41, 0x54, 0x78, 0xda, 0x63, 0x60, 0x70, 0x60, 0x68, 0xf8, 0x0f, 0x00, 0x03, 0x05, 0x01,
    0xc0, 0x53, 0x5b, 0x15, 0x9f, 0x00, 0x00, 0x00, 0x00, 0x49, 0x45, 0x4e, 0x44, 0xae, 0x42, 0x60, 0x82};

GltfMaterial material(const std::string& name)
{
    GltfMaterial m;
    m.name = name;
    m.baseColorFactor = glm::vec4(0.8f, 0.6f, 0.4f, 1.0f);
    m.metallicFactor = 0.0f;
    m.roughnessFactor = 0.5f;
    return m;
}

// Materials Body, Glass, Tyre, an unnamed one and a second "Body"; one texture already there.
GltfModel carModel()
{
    GltfModel model;
    model.file = "car.glb";
    model.materials = {material("Body"), material("Glass"), material("Tyre"), material(""), material("Body")};
    model.textures.resize(1);
    return model;
}

void expectVec3Eq(const glm::vec3& actual, const glm::vec3& expected)
{
    for (int i = 0; i < 3; ++i) {
        EXPECT_FLOAT_EQ(actual[i], expected[i]) << "component " << i;
    }
}

// `load` must throw InputError with a one-line message starting "FILE:"; returns the message.
std::string expectInputError(const std::function<void()>& load, const std::filesystem::path& file)
{
    try {
        load();
    } catch (const InputError& e) {
        const std::string message = e.what();
        EXPECT_EQ(message.rfind(file.string() + ":", 0), 0u) << message;
        EXPECT_EQ(message.find('\n'), std::string::npos) << message;
        return message;
    }
    ADD_FAILURE() << "expected InputError";
    return {};
}

MaterialOverrides loadText(const ScratchDir& dir, const std::string& text)
{
    const auto file = dir.file("car.materials.toml");
    test::writeText(file, text);
    return loadMaterialSidecar(file);
}

TEST(MaterialSidecar, ParsesPresetsAndOverridesAndAppliesThem)
{
    ScratchDir dir;
    const MaterialOverrides sidecar = loadText(dir, R"(# car.materials.toml
[material."*"]
preset = "plastic"

[material."Body"]
preset = "car_paint"
diffuse = [0.5, 0.02, 0.02]
specular = [0.05, 0.05, 0.06]
lobe = [-1.0, -0.9, 1.0]
exponent = 450
fresnel_phi = 0.25
tangent_rotation = 0.5

[material.Glass]
exponent = 1000.0
)");
    ASSERT_EQ(sidecar.materials.size(), 3u);
    const MaterialOverride& body = sidecar.materials.at("Body");
    EXPECT_EQ(body.line, 5);
    EXPECT_EQ(body.preset, "car_paint");
    ASSERT_TRUE(body.exponent.has_value());
    EXPECT_FLOAT_EQ(*body.exponent, 450.0f); // an integer is a number too
    EXPECT_EQ(body.rotationTexture, MaterialOverride::RotationTexture::Unset);

    GltfModel model = carModel();
    applyMaterialOverrides(model, sidecar);
    for (const size_t i : {size_t(0), size_t(4)}) { // both materials called Body
        const GltfMaterial& m = model.materials[i];
        EXPECT_TRUE(m.hasLafortune);
        expectVec3Eq(m.lafortune.diffuse, {0.5f, 0.02f, 0.02f});
        expectVec3Eq(m.lafortune.specular, {0.05f, 0.05f, 0.06f});
        expectVec3Eq(m.lafortune.lobe, {-1.0f, -0.9f, 1.0f});
        EXPECT_FLOAT_EQ(m.lafortune.exponent, 450.0f);
        EXPECT_FLOAT_EQ(m.lafortune.fresnelPhi, 0.25f);
        EXPECT_FLOAT_EQ(m.lafortune.tangentRotation, 0.5f);
        EXPECT_EQ(m.tangentRotationTexture, -1);
    }
    // Glass has no preset: its own metallic-roughness conversion with the exponent replaced.
    const LafortuneParams converted = lafortuneFromMetallicRoughness({0.8f, 0.6f, 0.4f}, 0.0f, 0.5f);
    const GltfMaterial& glass = model.materials[1];
    EXPECT_TRUE(glass.hasLafortune);
    EXPECT_FLOAT_EQ(glass.lafortune.exponent, 1000.0f);
    expectVec3Eq(glass.lafortune.diffuse, converted.diffuse);
    expectVec3Eq(glass.lafortune.specular, converted.specular);
    // Tyre and the unnamed material fall to "*": the plastic preset unchanged.
    const LafortuneParams plastic = *materialPreset("plastic");
    for (const size_t i : {size_t(2), size_t(3)}) {
        EXPECT_TRUE(model.materials[i].hasLafortune);
        expectVec3Eq(model.materials[i].lafortune.diffuse, plastic.diffuse);
        EXPECT_FLOAT_EQ(model.materials[i].lafortune.exponent, plastic.exponent);
    }
    EXPECT_EQ(model.textures.size(), 1u); // nothing appended
}

TEST(MaterialSidecar, FieldsOverrideTheMaterialsOwnLafortuneParameters)
{
    ScratchDir dir;
    GltfModel model = carModel();
    model.materials[1].hasLafortune = true;
    model.materials[1].lafortune.diffuse = glm::vec3(0.0f);
    model.materials[1].lafortune.exponent = 4096.0f;
    model.materials[1].lafortune.tangentRotation = 0.3f;
    model.materials[1].tangentRotationTexture = 0;
    applyMaterialOverrides(model, loadText(dir, "[material.Glass]\nfresnel_phi = 0.1\n"));
    const GltfMaterial& glass = model.materials[1];
    expectVec3Eq(glass.lafortune.diffuse, glm::vec3(0.0f));
    EXPECT_FLOAT_EQ(glass.lafortune.exponent, 4096.0f);
    EXPECT_FLOAT_EQ(glass.lafortune.fresnelPhi, 0.1f);
    EXPECT_FLOAT_EQ(glass.lafortune.tangentRotation, 0.3f); // the extension's own factor stays
    EXPECT_EQ(glass.tangentRotationTexture, 0);
    EXPECT_FALSE(model.materials[0].hasLafortune); // no "*": the others are untouched
}

TEST(MaterialSidecar, RotationTextures)
{
    ScratchDir dir;
    test::writeBytes(dir.file("grey.png"), kGreyPng);
    const MaterialOverrides sidecar = loadText(dir, R"(
[material.Body]
preset = "brushed_metal"          # brings the swirl along
[material.Glass]
tangent_rotation_texture = "swirl"
[material.Tyre]
tangent_rotation_texture = "grey.png"
tangent_rotation = 0.5
[material."*"]
preset = "brushed_metal"
tangent_rotation_texture = "none"
)");
    GltfModel model = carModel();
    applyMaterialOverrides(model, sidecar);
    // One swirl shared by Body (twice) and Glass, one image for Tyre: two textures appended.
    ASSERT_EQ(model.textures.size(), 3u);
    const int swirl = model.materials[0].tangentRotationTexture;
    ASSERT_GE(swirl, 1);
    EXPECT_EQ(model.materials[4].tangentRotationTexture, swirl);
    EXPECT_EQ(model.materials[1].tangentRotationTexture, swirl);
    const GltfTexture& swirlTexture = model.textures[size_t(swirl)];
    EXPECT_FALSE(swirlTexture.srgb);
    EXPECT_EQ(swirlTexture.image.data, makeSwirlRotationTexture(kSwirlRotationTextureSize).data);
    // A texture the sidecar attaches without a factor rotates by the texture itself.
    EXPECT_FLOAT_EQ(model.materials[0].lafortune.tangentRotation, 1.0f);
    EXPECT_FLOAT_EQ(model.materials[1].lafortune.tangentRotation, 1.0f);

    const GltfMaterial& tyre = model.materials[2];
    ASSERT_GE(tyre.tangentRotationTexture, 1);
    ASSERT_NE(tyre.tangentRotationTexture, swirl);
    EXPECT_FLOAT_EQ(tyre.lafortune.tangentRotation, 0.5f);
    const GltfTexture& grey = model.textures[size_t(tyre.tangentRotationTexture)];
    EXPECT_FALSE(grey.srgb);
    ASSERT_EQ(grey.image.width, 2);
    ASSERT_EQ(grey.image.channels, 4);
    const uint8_t expected[4] = {0, 64, 128, 255};
    for (int i = 0; i < 4; ++i) {
        const uint8_t* texel = grey.image.at(i % 2, i / 2);
        EXPECT_EQ(int(texel[0]), expected[i]);
        EXPECT_EQ(int(texel[1]), expected[i]);
        EXPECT_EQ(int(texel[3]), 255);
    }
    // "*" asked for brushed metal without its swirl.
    EXPECT_EQ(model.materials[3].tangentRotationTexture, -1);
    EXPECT_EQ(model.materials[3].lafortune.tangentRotation, 0.0f);
    expectVec3Eq(model.materials[3].lafortune.lobe, materialPreset("brushed_metal")->lobe);
}

TEST(MaterialSidecar, UnknownMaterialNameListsTheModelsMaterials)
{
    ScratchDir dir;
    const MaterialOverrides sidecar = loadText(dir, "[material.Body]\npreset = \"chrome\"\n\n[material.Bdy]\n");
    GltfModel model = carModel();
    try {
        applyMaterialOverrides(model, sidecar);
        ADD_FAILURE() << "expected InputError";
    } catch (const InputError& e) {
        const std::string expected = sidecar.source + ":4: material \"Bdy\" matches no material of car.glb " +
                                     "(its materials: \"Body\", \"Glass\", \"Tyre\")";
        EXPECT_EQ(std::string(e.what()), expected);
    }
    EXPECT_FALSE(model.materials[0].hasLafortune); // checked before anything changed
}

struct BadSidecar {
    const char* text;
    int line;
    const char* expected; // after "FILE:LINE: "
};

const BadSidecar kBadSidecars[] = {
    {"[material.Body]\npreset = \"chrome\n", 2, ""}, // TOML syntax: unterminated string
    {"foo = 1\n", 1, "foo: unknown key"},
    {"material = 5\n", 1, "material: expected a table"},
    {"[material]\nBody = 3\n", 2, "material.\"Body\": expected a table, found an integer"},
    {"\n[material.Body]\ndifuse = [0.5, 0.5, 0.5]\n", 3, "material.\"Body\".difuse: unknown key"},
    {"[material.Body]\npreset = \"gold\"\n", 2,
     "material.\"Body\".preset: \"gold\" is not one of chrome, brushed_metal, car_paint"},
    {"[material.Body]\npreset = 3\n", 2, "material.\"Body\".preset: expected a string, found an integer"},
    {"[material.Body]\n\ndiffuse = \"red\"\n", 3, "material.\"Body\".diffuse: expected an array of 3 numbers"},
    {"[material.Body]\ndiffuse = [0.5, 0.5]\n", 2, "material.\"Body\".diffuse: expected an array of 3 numbers"},
    {"[material.Body]\ndiffuse = [0.5, 1.5, 0.5]\n", 2,
     "material.\"Body\".diffuse: expected an array of 3 numbers "
     "within [0, 1]"},
    {"[material.Body]\nspecular = [0.5, -0.1, 0.5]\n", 2, "material.\"Body\".specular: expected an array"},
    {"[material.Body]\nlobe = [0, 0, 0]\n", 2, "material.\"Body\".lobe: all three coefficients are 0"},
    {"[material.Body]\nlobe = [-5, -1, 1]\n", 2,
     "material.\"Body\".lobe: expected an array of 3 numbers within [-4, 4]"},
    {"[material.Body]\nexponent = 0.5\n", 2, "material.\"Body\".exponent: 0.5 is outside [1, 4096]"},
    {"[material.Body]\nexponent = 5000\n", 2, "material.\"Body\".exponent: 5000 is outside [1, 4096]"},
    {"[material.Body]\nexponent = \"500\"\n", 2, "material.\"Body\".exponent: expected a number, found a string"},
    {"[material.Body]\nexponent = nan\n", 2, "material.\"Body\".exponent: nan is outside [1, 4096]"},
    {"[material.Body]\nfresnel_phi = 1.0\n", 2, "material.\"Body\".fresnel_phi: 1 is outside [0, 1)"},
    {"[material.Body]\ntangent_rotation = 2\n", 2, "material.\"Body\".tangent_rotation: 2 is outside [0, 1]"},
    {"[material.Body]\ntangent_rotation = true\n", 2, "material.\"Body\".tangent_rotation: expected a number"},
    {"[material.Body]\ntangent_rotation_texture = \"\"\n", 2,
     "material.\"Body\".tangent_rotation_texture: must be \"swirl\", \"none\" or an image path"},
    {"[material.Body]\ntangent_rotation_texture = \"missing.png\"\n", 2,
     "material.\"Body\".tangent_rotation_texture: "}, // + path + ": no such file", checked below
    {"[material.Body]\ntangent_rotation_texture = \"not_an_image.png\"\n", 2,
     "material.\"Body\".tangent_rotation_texture: "},
};

TEST(MaterialSidecar, MalformedInputNamesFileAndLine)
{
    ScratchDir dir;
    test::writeText(dir.file("not_an_image.png"), "this is text, not a PNG\n");
    const auto file = dir.file("car.materials.toml");
    for (const BadSidecar& c : kBadSidecars) {
        SCOPED_TRACE(c.text);
        test::writeText(file, c.text);
        const std::string message = expectInputError([&] { loadMaterialSidecar(file); }, file);
        const std::string prefix = file.string() + ":" + std::to_string(c.line) + ": ";
        EXPECT_EQ(message.rfind(prefix + c.expected, 0), 0u) << message;
    }
    // The texture failures name the resolved path and the reason.
    test::writeText(file, "[material.Body]\ntangent_rotation_texture = \"missing.png\"\n");
    const std::string missing = expectInputError([&] { loadMaterialSidecar(file); }, file);
    EXPECT_NE(missing.find(dir.file("missing.png").string() + ": no such file"), std::string::npos) << missing;
    test::writeText(file, "[material.Body]\ntangent_rotation_texture = \"not_an_image.png\"\n");
    const std::string corrupt = expectInputError([&] { loadMaterialSidecar(file); }, file);
    EXPECT_NE(corrupt.find("not_an_image.png: cannot decode"), std::string::npos) << corrupt;

    const auto absent = dir.file("absent.toml");
    const std::string noFile = expectInputError([&] { loadMaterialSidecar(absent); }, absent);
    EXPECT_EQ(noFile, absent.string() + ": no such file");
}

TEST(MaterialSidecar, EmptyFileChangesNothing)
{
    ScratchDir dir;
    const MaterialOverrides sidecar = loadText(dir, "# nothing yet\n");
    EXPECT_TRUE(sidecar.materials.empty());
    GltfModel model = carModel();
    applyMaterialOverrides(model, sidecar);
    for (const GltfMaterial& m : model.materials) {
        EXPECT_FALSE(m.hasLafortune);
    }
}

} // namespace
} // namespace lumar
