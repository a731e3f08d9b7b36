// LUMAR_materials_lafortune on hand-written glTF files: every field read into GltfMaterial,
// defaults from the metallic-roughness conversion, textures in the right colour space, and
// each malformed field rejected with the file, the material (index and name) and the field.
#include <string>

#include <gtest/gtest.h>

#include "gles_renderer/assets/gltf_model.h"
#include "gles_renderer/assets/lafortune_material.h"
#include "mini_gltf.h"
#include "render_test_support.h"

namespace lumar {
namespace {

using test::MiniGltf;
using test::oneTriangle;
using test::ScratchDir;

// A 1x1 RGB PNG holding (200, 100, 50), as a data URI.
const char* const kPngDataUri =
    "data:image/png;base64,"
    "iVBORw0KGgoAAAANSUhEUgAAAAEAAAABCAIAAACQd1PeAAAADElEQVR42mM4kWIEAANWAV/W6lf+AAAAAElFTkSuQmCC";

// Two images (the same pixel) and three textures: 0 and 1 use image 0, 2 uses image 1.
std::string imagesAndTextures()
{
    return std::string(R"(,"images":[{"uri":")") + kPngDataUri + R"("},{"uri":")" + kPngDataUri +
           R"("}],"textures":[{"source":0},{"source":0},{"source":1}])";
}

// One material named Body with base colour (0.8, 0.6, 0.4), metallic 0.25, roughness 0.5 and
// the extension object `extension` (JSON).
MiniGltf withExtension(const std::string& extension, const std::string& name = "Body")
{
    MiniGltf g = oneTriangle();
    g.materials = std::string("{") + (name.empty() ? "" : R"("name":")" + name + R"(",)") +
                  R"("pbrMetallicRoughness":{"baseColorFactor":[0.8,0.6,0.4,1],"metallicFactor":0.25,)"
                  R"("roughnessFactor":0.5},"extensions":{"LUMAR_materials_lafortune":)" +
                  extension + "}}";
    g.extra = imagesAndTextures();
    return g;
}

void expectVec3Eq(const glm::vec3& actual, const glm::vec3& expected)
{
    for (int i = 0; i < 3; ++i) {
        EXPECT_FLOAT_EQ(actual[i], expected[i]) << "component " << i;
    }
}

TEST(GltfLafortuneExtension, ReadsEveryField)
{
    ScratchDir dir;
    MiniGltf g = withExtension(R"({"diffuseFactor":[0.5,0.02,0.03],"diffuseTexture":{"index":0},)"
                               R"("specularFactor":[0.05,0.06,0.07],"specularTexture":{"index":1},)"
                               R"("lobeFactor":[-1.0,-0.8,0.9],"exponentFactor":500,"lobeTexture":{"index":0},)"
                               R"("fresnelPhi":0.2,"tangentRotation":0.25,"tangentRotationTexture":{"index":2}})");
    g.extra += R"(,"extensionsUsed":["LUMAR_materials_lafortune"],"extensionsRequired":["LUMAR_materials_lafortune"])";
    const GltfModel model = loadGltfModel(g.write(dir, "full"));
    ASSERT_EQ(model.materials.size(), 1u);
    const GltfMaterial& m = model.materials[0];
    EXPECT_TRUE(m.hasLafortune);
    expectVec3Eq(m.lafortune.diffuse, {0.5f, 0.02f, 0.03f});
    expectVec3Eq(m.lafortune.specular, {0.05f, 0.06f, 0.07f});
    expectVec3Eq(m.lafortune.lobe, {-1.0f, -0.8f, 0.9f});
    EXPECT_FLOAT_EQ(m.lafortune.exponent, 500.0f);
    EXPECT_FLOAT_EQ(m.lafortune.fresnelPhi, 0.2f);
    EXPECT_FLOAT_EQ(m.lafortune.tangentRotation, 0.25f);

    // Textures: image 0 as sRGB (diffuse; specular shares it), image 0 as linear (lobe),
    // image 1 as linear (rotation).
    ASSERT_EQ(model.textures.size(), 3u);
    ASSERT_GE(m.baseColorTexture, 0);
    ASSERT_GE(m.specularTexture, 0);
    ASSERT_GE(m.lobeTexture, 0);
    ASSERT_GE(m.tangentRotationTexture, 0);
    EXPECT_EQ(m.baseColorTexture, m.specularTexture); // same image, both sRGB
    EXPECT_TRUE(model.textures[size_t(m.baseColorTexture)].srgb);
    EXPECT_FALSE(model.textures[size_t(m.lobeTexture)].srgb);
    EXPECT_FALSE(model.textures[size_t(m.tangentRotationTexture)].srgb);
    EXPECT_NE(m.lobeTexture, m.tangentRotationTexture);
    const uint8_t* texel = model.textures[size_t(m.tangentRotationTexture)].image.at(0, 0);
    EXPECT_EQ(int(texel[0]), 200);
    EXPECT_EQ(int(texel[1]), 100);
    EXPECT_EQ(int(texel[2]), 50);
    EXPECT_EQ(int(texel[3]), 255);
}

TEST(GltfLafortuneExtension, AbsentFieldsComeFromTheMetallicRoughnessConversion)
{
    ScratchDir dir;
    const LafortuneParams converted = lafortuneFromMetallicRoughness({0.8f, 0.6f, 0.4f}, 0.25f, 0.5f);
    // base (1 - 0.25) and mix(0.04, base, 0.25); roughness 0.5 -> n 30.
    expectVec3Eq(converted.diffuse, {0.6f, 0.45f, 0.3f});
    expectVec3Eq(converted.specular, {0.23f, 0.18f, 0.13f});
    EXPECT_NEAR(converted.exponent, 30.0f, 1e-4f);

    const GltfModel empty = loadGltfModel(withExtension("{}").write(dir, "empty"));
    const GltfMaterial& e = empty.materials[0];
    EXPECT_TRUE(e.hasLafortune);
    expectVec3Eq(e.lafortune.diffuse, converted.diffuse);
    expectVec3Eq(e.lafortune.specular, converted.specular);
    expectVec3Eq(e.lafortune.lobe, converted.lobe);
    EXPECT_FLOAT_EQ(e.lafortune.exponent, converted.exponent);
    EXPECT_FLOAT_EQ(e.lafortune.fresnelPhi, kMetallicRoughnessFresnelPhi);
    EXPECT_EQ(e.lafortune.tangentRotation, 0.0f);
    EXPECT_EQ(e.specularTexture, -1);
    EXPECT_EQ(e.lobeTexture, -1);
    EXPECT_EQ(e.tangentRotationTexture, -1);
    EXPECT_EQ(e.baseColorTexture, -1);

    const GltfModel partial = loadGltfModel(withExtension(R"({"exponentFactor":77.5})").write(dir, "partial"));
    EXPECT_FLOAT_EQ(partial.materials[0].lafortune.exponent, 77.5f);
    expectVec3Eq(partial.materials[0].lafortune.diffuse, converted.diffuse);

    // A rotation texture without a factor rotates by the texture (factor 1), not by 0 x texel.
    const GltfModel rotated =
        loadGltfModel(withExtension(R"({"tangentRotationTexture":{"index":2,"texCoord":0}})").write(dir, "rot"));
    EXPECT_EQ(rotated.materials[0].lafortune.tangentRotation, 1.0f);
    EXPECT_GE(rotated.materials[0].tangentRotationTexture, 0);

    MiniGltf plain = oneTriangle();
    plain.materials = R"({"name":"Plain","pbrMetallicRoughness":{"metallicFactor":0.0}})";
    EXPECT_FALSE(loadGltfModel(plain.write(dir, "plain")).materials[0].hasLafortune);
}

struct MalformedCase {
    const char* extension;
    const char* field;   // must appear in the message
    const char* problem; // must appear in the message
};

const MalformedCase kMalformed[] = {
    {R"({"diffuseFactor":[1,1]})", "diffuseFactor", "expected an array of 3 numbers"},
    {R"({"diffuseFactor":[1,1,1,1]})", "diffuseFactor", "found 4"},
    {R"({"diffuseFactor":"red"})", "diffuseFactor", "expected an array of 3 numbers"},
    {R"({"diffuseFactor":[0.5,"x",0.5]})", "diffuseFactor", "expected an array of 3 numbers"},
    {R"({"diffuseFactor":[0.5,1.5,0.5]})", "diffuseFactor", "within [0, 1]"},
    {R"({"specularFactor":[0.5,0.5,-0.1]})", "specularFactor", "within [0, 1]"},
    {R"({"lobeFactor":[0,0,0]})", "lobeFactor", "no direction"},
    {R"({"lobeFactor":[-5,-1,1]})", "lobeFactor", "within [-4, 4]"},
    {R"({"exponentFactor":"500"})", "exponentFactor", "expected a number"},
    {R"({"exponentFactor":0.5})", "exponentFactor", "0.5 is outside [1, 4096]"},
    {R"({"exponentFactor":5000})", "exponentFactor", "5000 is outside [1, 4096]"},
    {R"({"fresnelPhi":1.0})", "fresnelPhi", "1 is outside [0, 1)"},
    {R"({"fresnelPhi":-0.1})", "fresnelPhi", "is outside [0, 1)"},
    {R"({"fresnelPhi":true})", "fresnelPhi", "expected a number"},
    {R"({"tangentRotation":1.5})", "tangentRotation", "1.5 is outside [0, 1]"},
    {R"({"diffuseTexture":{"index":7}})", "diffuseTexture", "texture 7 does not exist"},
    {R"({"specularTexture":{"index":3}})", "specularTexture", "texture 3 does not exist"},
    {R"({"specularTexture":1})", "specularTexture", "expected a textureInfo object"},
    {R"({"lobeTexture":{"index":-1}})", "lobeTexture", "non-negative integer"},
    {R"({"lobeTexture":{"index":0.5}})", "lobeTexture", "non-negative integer"},
    {R"({"tangentRotationTexture":{"texCoord":0}})", "tangentRotationTexture", "index is missing"},
    {R"({"tangentRotationTexture":{"index":0,"texCoord":"0"}})", "tangentRotationTexture", "texCoord"},
    {R"({"tangentRotationTexture":{"index":0,"scale":2}})", "tangentRotationTexture", "unknown field scale"},
    {R"({"diffuse":[0.5,0.5,0.5]})", "diffuse", "unknown field"},
};

TEST(GltfLafortuneExtension, MalformedFieldsNameFileMaterialAndField)
{
    ScratchDir dir;
    // The same file with a valid extension loads, so each failure is the field's.
    ASSERT_TRUE(loadGltfModel(withExtension(R"({"exponentFactor":10})").write(dir, "good")).materials[0].hasLafortune);
    for (const MalformedCase& c : kMalformed) {
        SCOPED_TRACE(c.extension);
        const auto file = withExtension(c.extension).write(dir, "bad");
        const std::string message = test::expectInputErrorNamingFile([&] { loadGltfModel(file); }, file);
        EXPECT_NE(message.find("material 0 (\"Body\")"), std::string::npos) << message;
        EXPECT_NE(message.find(std::string("LUMAR_materials_lafortune.") + c.field + ":"), std::string::npos)
            << message;
        EXPECT_NE(message.find(c.problem), std::string::npos) << message;
    }
    // An unnamed material is named by its index alone.
    const auto unnamed = withExtension(R"({"exponentFactor":0})", "").write(dir, "unnamed");
    const std::string message = test::expectInputErrorNamingFile([&] { loadGltfModel(unnamed); }, unnamed);
    EXPECT_NE(message.find("material 0 (unnamed) LUMAR_materials_lafortune.exponentFactor: 0 is outside"),
              std::string::npos)
        << message;
}

} // namespace
} // namespace lumar
