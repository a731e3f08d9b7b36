// The loader's side of issue 20's static-model features: samplers, COLOR_0, TEXCOORD_1 and
// texCoord, occlusion, KHR_texture_transform, KHR_mesh_quantization, KHR_materials_unlit,
// alpha modes, EXT_mesh_gpu_instancing, WebP images; and every rejection in our words.
#include <cmath>
#include <string>
#include <vector>

#include <glm/gtc/constants.hpp>
#include <gtest/gtest.h>
#include <webp/encode.h>

#include "feature_gltf.h"
#include "gles_renderer/assets/gltf_model.h"
#include "mini_gltf.h"
#include "render_test_support.h"

namespace lumar {
namespace {

using test::FeatureGltf;
using test::ScratchDir;

const std::array<uint8_t, 4> kRed{255, 0, 0, 255}, kGreen{0, 255, 0, 255};

std::string expectRejected(const std::filesystem::path& file)
{
    const std::string message = test::expectInputErrorNamingFile([&] { (void)loadGltfModel(file); }, file);
    // tinygltf's and nlohmann's own wording never reaches the user.
    for (const char* raw : {"json.exception", "'uri' is missing", "STB", "invalid bufferView", "property is",
                            "tinygltf", "Failed to", "[", "`"}) {
        EXPECT_EQ(message.find(raw), std::string::npos) << "raw wording \"" << raw << "\" in: " << message;
    }
    return message;
}

void expectMessage(const std::filesystem::path& file, const std::string& expected)
{
    const std::string message = expectRejected(file);
    EXPECT_NE(message.find(expected), std::string::npos) << message;
}

TEST(GltfStaticFeatures, SamplersAreReadPerTexture)
{
    ScratchDir dir;
    FeatureGltf g;
    const Image8 image = test::texelImage(2, 1, {kRed, kGreen});
    const int clamp = g.texture(dir, "a", image, R"({"wrapS":33071,"wrapT":33648,"magFilter":9728,"minFilter":9728})");
    const int repeat = g.texture(dir, "b", image, R"({})");
    const int m0 =
        g.material(R"({"pbrMetallicRoughness":{"baseColorTexture":{"index":)" + std::to_string(clamp) + "}}}");
    const int m1 =
        g.material(R"({"pbrMetallicRoughness":{"baseColorTexture":{"index":)" + std::to_string(repeat) + "}}}");
    g.primitive(g.quadAttributes(0, 0, 1, 1, 0, 0, 0, 1, 1), m0);
    g.primitive(g.quadAttributes(0, 0, 1, 1, 0, 0, 0, 1, 1), m1);
    const GltfModel model = loadGltfModel(g.save(dir, "samplers"));
    ASSERT_EQ(model.textures.size(), 2u);
    ASSERT_EQ(model.textureSamplers.size(), 2u);
    const GltfSampler& a = model.textureSamplers[size_t(model.materials[0].baseColorTexture)];
    EXPECT_EQ(a.wrapS, 33071);
    EXPECT_EQ(a.wrapT, 33648);
    EXPECT_EQ(a.magFilter, 9728);
    EXPECT_EQ(a.minFilter, 9728);
    const GltfSampler& b = model.textureSamplers[size_t(model.materials[1].baseColorTexture)];
    EXPECT_EQ(b.wrapS, 10497);
    EXPECT_EQ(b.minFilter, 0) << "none given: lumar's default";
}

TEST(GltfStaticFeatures, AnUnknownWrapValueNamesTheSampler)
{
    ScratchDir dir;
    FeatureGltf g;
    g.texture(dir, "a", test::texelImage(1, 1, {kRed}), R"({})");
    const int bad = g.texture(dir, "b", test::texelImage(1, 1, {kRed}), R"({"wrapT":1234})");
    g.primitive(g.quadAttributes(0, 0, 1, 1, 0, 0, 0, 1, 1),
                g.material(R"({"pbrMetallicRoughness":{"baseColorTexture":{"index":)" + std::to_string(bad) + "}}}"));
    expectMessage(g.save(dir, "wrap"), "sampler 1: wrapT 1234 is not a glTF wrap mode");
}

TEST(GltfStaticFeatures, VertexColoursSecondUvsAndTexCoords)
{
    ScratchDir dir;
    FeatureGltf g;
    const int rgb = g.accessor<float>({1, 0, 0, 0, 1, 0, 0, 0, 1, 1, 1, 1}, 5126, "VEC3", 4);
    const int rgba =
        g.accessor<uint8_t>({255, 0, 0, 255, 0, 255, 0, 128, 0, 0, 255, 0, 51, 51, 51, 255}, 5121, "VEC4", 4, true);
    const int uv1 = g.accessor<uint16_t>({0, 0, 65535, 0, 65535, 65535, 0, 65535}, 5123, "VEC2", 4, true);
    const int texture = g.texture(dir, "t", test::texelImage(1, 1, {kRed}));
    const int m = g.material(R"({"pbrMetallicRoughness":{"baseColorTexture":{"index":)" + std::to_string(texture) +
                             R"(,"texCoord":1}},"occlusionTexture":{"index":)" + std::to_string(texture) +
                             R"(,"strength":0.25,"texCoord":1}})");
    g.primitive(g.quadAttributes(0, 0, 1, 1, 0, 0, 0, 1, 1) + R"(,"COLOR_0":)" + std::to_string(rgb) +
                    R"(,"TEXCOORD_1":)" + std::to_string(uv1),
                m);
    g.primitive(g.quadAttributes(0, 0, 1, 1, 0, 0, 0, 1, 1) + R"(,"COLOR_0":)" + std::to_string(rgba), m);
    const GltfModel model = loadGltfModel(g.save(dir, "colours"));
    ASSERT_EQ(model.primitives.size(), 2u);
    const GltfPrimitive& a = model.primitives[0];
    ASSERT_EQ(a.colors.size(), 4u);
    EXPECT_EQ(a.colors[1], glm::vec4(0, 1, 0, 1)) << "VEC3 colours get alpha 1";
    ASSERT_EQ(a.uvs1.size(), 4u);
    EXPECT_EQ(a.uvs1[2], glm::vec2(1, 1));
    const GltfPrimitive& b = model.primitives[1];
    EXPECT_TRUE(b.uvs1.empty());
    EXPECT_NEAR(b.colors[1].a, 128.0f / 255.0f, 1e-6f);
    EXPECT_NEAR(b.colors[3].r, 0.2f, 1e-6f);
    const GltfMaterial& material = model.materials[0];
    EXPECT_EQ(material.uvTransforms[size_t(GltfTextureSlot::BaseColor)].texCoord, 1);
    EXPECT_EQ(material.uvTransforms[size_t(GltfTextureSlot::Occlusion)].texCoord, 1);
    EXPECT_GE(material.occlusionTexture, 0);
    EXPECT_FLOAT_EQ(material.occlusionStrength, 0.25f);
}

TEST(GltfStaticFeatures, TextureTransformAsTheExtensionDefinesIt)
{
    ScratchDir dir;
    FeatureGltf g;
    const int texture = g.texture(dir, "t", test::texelImage(1, 1, {kRed}));
    const int m = g.material(R"({"pbrMetallicRoughness":{"baseColorTexture":{"index":)" + std::to_string(texture) +
                             R"(,"extensions":{"KHR_texture_transform":{"offset":[0.5,0.25],"rotation":1.5707963,)"
                             R"("scale":[2,3],"texCoord":1}}}}})");
    g.primitive(g.quadAttributes(0, 0, 1, 1, 0, 0, 0, 1, 1), m);
    g.extensionsUsed = {"KHR_texture_transform"};
    g.extensionsRequired = {"KHR_texture_transform"};
    const GltfModel model = loadGltfModel(g.save(dir, "transform"));
    const GltfUvTransform& t = model.materials[0].uvTransforms[size_t(GltfTextureSlot::BaseColor)];
    EXPECT_EQ(t.texCoord, 1) << "the extension's texCoord overrides the textureInfo's";
    // The extension's example: uv (1, 0) scaled to (2, 0), rotated by pi/2 to (0, -2)
    // (its rotation matrix is (cos, sin; -sin, cos)), offset to (0.5, -1.75).
    const auto rows = t.rows();
    const glm::vec3 uv(1, 0, 1);
    EXPECT_NEAR(glm::dot(rows[0], uv), 0.5f, 1e-5f);
    EXPECT_NEAR(glm::dot(rows[1], uv), -1.75f, 1e-5f);
}

TEST(GltfStaticFeatures, QuantizedAttributes)
{
    ScratchDir dir;
    FeatureGltf g;
    // Positions as signed shorts (not normalized, as KHR_mesh_quantization allows), normals
    // as normalized bytes, uvs as normalized unsigned bytes.
    const int position = g.accessor<int16_t>({0, 0, 0, 0, 100, 0, 0, 0, -100, 100, 0, 0}, 5122, "VEC3", 4);
    const int normal = g.accessor<int8_t>({0, 0, 127, 0, 0, 0, 127, 0, 0, 0, -128, 0}, 5120, "VEC3", 4, true);
    const int uv = g.accessor<uint8_t>({0, 0, 255, 0, 255, 255, 0, 255}, 5121, "VEC2", 4, true);
    const int indices = g.accessor<uint16_t>({0, 1, 2, 0, 2, 3}, 5123, "SCALAR", 6);
    g.primitives.push_back(R"({"attributes":{"POSITION":)" + std::to_string(position) + R"(,"NORMAL":)" +
                           std::to_string(normal) + R"(,"TEXCOORD_0":)" + std::to_string(uv) + R"(},"indices":)" +
                           std::to_string(indices) + "}");
    g.node = R"({"mesh":0,"scale":[0.01,0.01,0.01]})";
    g.extensionsUsed = {"KHR_mesh_quantization"};
    g.extensionsRequired = {"KHR_mesh_quantization"};
    const GltfModel model = loadGltfModel(g.save(dir, "quantized"));
    const GltfPrimitive& p = model.primitives.at(0);
    EXPECT_EQ(p.positions[1], glm::vec3(0, 100, 0));
    EXPECT_EQ(p.positions[2], glm::vec3(0, 0, -100));
    EXPECT_NEAR(glm::distance(p.normals[0], glm::vec3(0, 0, 1)), 0.0f, 1e-6f);
    EXPECT_NEAR(glm::distance(p.normals[3], glm::vec3(0, -1, 0)), 0.0f, 1e-6f) << "-128 clamps to -1";
    EXPECT_EQ(p.uvs[2], glm::vec2(1, 1));
    EXPECT_NEAR(model.boundsMax.y, 1.0f, 1e-6f) << "the node's scale undoes the quantization";
}

TEST(GltfStaticFeatures, UnlitAndAlphaModes)
{
    ScratchDir dir;
    FeatureGltf g;
    g.primitive(g.quadAttributes(0, 0, 1, 1, 0, 0, 0, 1, 1),
                g.material(R"({"extensions":{"KHR_materials_unlit":{}},"alphaMode":"MASK","alphaCutoff":0.3})"));
    g.primitive(g.quadAttributes(0, 0, 1, 1, 0, 0, 0, 1, 1), g.material(R"({"alphaMode":"BLEND"})"));
    g.primitive(g.quadAttributes(0, 0, 1, 1, 0, 0, 0, 1, 1), g.material(R"({})"));
    g.extensionsUsed = {"KHR_materials_unlit"};
    g.extensionsRequired = {"KHR_materials_unlit"};
    const GltfModel model = loadGltfModel(g.save(dir, "unlit"));
    EXPECT_TRUE(model.materials[0].unlit);
    EXPECT_EQ(model.materials[0].alphaMode, GltfAlphaMode::Mask);
    EXPECT_FLOAT_EQ(model.materials[0].alphaCutoff, 0.3f);
    EXPECT_EQ(model.materials[1].alphaMode, GltfAlphaMode::Blend);
    EXPECT_FALSE(model.materials[2].unlit);
    EXPECT_EQ(model.materials[2].alphaMode, GltfAlphaMode::Opaque);

    FeatureGltf bad;
    bad.primitive(bad.quadAttributes(0, 0, 1, 1, 0, 0, 0, 1, 1), bad.material(R"({"alphaMode":"CUTOUT"})"));
    expectMessage(bad.save(dir, "badalpha"), "alphaMode \"CUTOUT\" is not OPAQUE, MASK or BLEND");
}

TEST(GltfStaticFeatures, GpuInstancingExpandsIntoInstances)
{
    ScratchDir dir;
    FeatureGltf g;
    g.primitive(g.quadAttributes(0, 0, 1, 1, 0, 0, 0, 1, 1), g.material("{}"));
    const int translation = g.accessor<float>({0, 0, 0, 2, 0, 0, 4, 0, 0}, 5126, "VEC3", 3);
    // Normalized shorts: the identity and a half turn about z.
    const int rotation = g.accessor<int16_t>({0, 0, 0, 32767, 0, 0, 32767, 0, 0, 0, 0, 32767}, 5122, "VEC4", 3, true);
    const int scale = g.accessor<float>({1, 1, 1, 1, 1, 1, 1, 2, 1}, 5126, "VEC3", 3);
    g.node = R"({"mesh":0,"translation":[0,0,-1],"extensions":{"EXT_mesh_gpu_instancing":{"attributes":{)"
             R"("TRANSLATION":)" +
             std::to_string(translation) + R"(,"ROTATION":)" + std::to_string(rotation) + R"(,"SCALE":)" +
             std::to_string(scale) + "}}}}";
    g.extensionsUsed = {"EXT_mesh_gpu_instancing"};
    g.extensionsRequired = {"EXT_mesh_gpu_instancing"};
    const GltfModel model = loadGltfModel(g.save(dir, "instances"));
    ASSERT_EQ(model.primitives.size(), 3u);
    const auto place = [&](size_t instance, glm::vec3 p) {
        return glm::vec3(model.primitives[instance].modelFromMesh * glm::vec4(p, 1.0f));
    };
    EXPECT_NEAR(glm::distance(place(0, {1, 1, 0}), glm::vec3(1, 1, -1)), 0.0f, 1e-5f);
    EXPECT_NEAR(glm::distance(place(1, {1, 1, 0}), glm::vec3(1, -1, -1)), 0.0f, 1e-4f) << "turned about z";
    EXPECT_NEAR(glm::distance(place(2, {1, 1, 0}), glm::vec3(5, 2, -1)), 0.0f, 1e-5f) << "scaled in y";
}

TEST(GltfStaticFeatures, WebpImagesAreDecoded)
{
    ScratchDir dir;
    FeatureGltf g;
    const Image8 image = test::texelImage(2, 1, {kRed, kGreen});
    uint8_t* encoded = nullptr;
    const size_t size = WebPEncodeLosslessRGBA(image.data.data(), 2, 1, 8, &encoded);
    ASSERT_GT(size, 0u);
    test::writeBytes(dir.file("t.webp"), std::vector<uint8_t>(encoded, encoded + size));
    WebPFree(encoded);
    g.images.push_back(R"({"uri":"t.webp"})");
    g.textures.push_back(R"({"extensions":{"EXT_texture_webp":{"source":0}}})");
    g.primitive(g.quadAttributes(0, 0, 1, 1, 0, 0, 0, 1, 1),
                g.material(R"({"pbrMetallicRoughness":{"baseColorTexture":{"index":0}}})"));
    g.extensionsUsed = {"EXT_texture_webp"};
    g.extensionsRequired = {"EXT_texture_webp"};
    const GltfModel model = loadGltfModel(g.save(dir, "webp"));
    ASSERT_EQ(model.textures.size(), 1u);
    const Image8& decoded = model.textures[0].image;
    ASSERT_EQ(decoded.width, 2);
    EXPECT_EQ(decoded.at(0, 0)[0], 255);
    EXPECT_EQ(decoded.at(1, 0)[1], 255);
    EXPECT_EQ(decoded.at(1, 0)[0], 0);
}

// Deliverable 4: each rejection in one line of our words.
TEST(GltfStaticFeatures, RejectionsInOurWords)
{
    ScratchDir dir;
    const auto triangle = [] { return test::oneTriangle(); };

    test::MiniGltf required = triangle();
    required.extra = R"(,"extensionsUsed":["KHR_xyz_magic"],"extensionsRequired":["KHR_xyz_magic"])";
    expectMessage(required.write(dir, "required"), "requires extension KHR_xyz_magic, which lumar does not support");

    // A .gltf whose buffer has no uri.
    const auto noUri = dir.file("nouri.gltf");
    test::writeText(noUri, R"({"asset":{"version":"2.0"},"buffers":[{"byteLength":12}]})");
    expectMessage(noUri, "buffer 0 has no uri and the file is not a .glb");

    // nlohmann's number overflow and syntax errors.
    const auto overflow = dir.file("overflow.gltf");
    test::writeText(overflow, R"({"asset":{"version":"2.0"},"scene":1e999999})");
    expectMessage(overflow, "the JSON holds a number too large to read");
    const auto syntax = dir.file("syntax.gltf");
    test::writeText(syntax, R"({"asset":{"version":"2.0"},)");
    expectMessage(syntax, "the JSON is malformed near byte");

    // Indices accessor without a bufferView (how a Draco file looks to a loader without Draco).
    test::MiniGltf indices = triangle();
    indices.accessors = R"({"bufferView":0,"componentType":5126,"count":3,"type":"VEC3"},)"
                        R"({"componentType":5123,"count":3,"type":"SCALAR"})";
    expectMessage(indices.write(dir, "indices"), "accessor 1, a primitive's indices, has no bufferView");

    // An image that is no image.
    test::MiniGltf image = triangle();
    test::writeText(dir.file("junk.png"), "this is not a picture at all");
    image.extra = R"(,"images":[{"uri":"junk.png"}],"textures":[{"source":0}])";
    image.materials = R"({"pbrMetallicRoughness":{"baseColorTexture":{"index":0}}})";
    expectMessage(image.write(dir, "junk"), "image 0 is not an image lumar can decode (PNG, JPEG or WebP)");

    // A missing buffer file.
    test::MiniGltf missing = triangle();
    const auto missingFile = missing.write(dir, "missing");
    std::filesystem::remove(dir.file("missing.bin"));
    expectMessage(missingFile, "buffer 0's file 'missing.bin' does not exist");

    // A required field missing.
    const auto noCount = dir.file("nocount.gltf");
    test::writeText(noCount, R"({"asset":{"version":"2.0"},"accessors":[{"componentType":5126,"type":"VEC3"}]})");
    expectMessage(noCount, "required field \"count\"");

    // An image with neither uri nor bufferView.
    const auto emptyImage = dir.file("emptyimage.gltf");
    test::writeText(emptyImage, R"({"asset":{"version":"2.0"},"images":[{"mimeType":"image/png"}]})");
    expectMessage(emptyImage, "image 0 has neither a uri nor a bufferView");
}

TEST(GltfStaticFeatures, PointsAndLinesAreSkippedNamingThePrimitive)
{
    ScratchDir dir;
    test::MiniGltf g = test::oneTriangle();
    g.meshes = R"({"primitives":[{"attributes":{"POSITION":0},"mode":1},{"attributes":{"POSITION":0},"indices":1}]})";
    const GltfModel model = loadGltfModel(g.write(dir, "lines"));
    EXPECT_EQ(model.primitives.size(), 1u) << "the lines are skipped with a warning, the triangle drawn";
}

// Generated tangents follow the normal map's uv set: with normalTexture.texCoord 1 (or
// KHR_texture_transform's texCoord 1) the second set, whose +u runs along -y here, and whose
// image-up (-v) runs along -x, so cross(N, T) = +x needs w = -1; the first set's +u runs along +x.
TEST(GltfStaticFeatures, GeneratedTangentsFollowTheNormalMapsUvSet)
{
    ScratchDir dir;
    FeatureGltf g;
    const int texture = g.texture(dir, "n", test::texelImage(1, 1, {{128, 128, 255, 255}}));
    const std::string index = std::to_string(texture);
    const int onSecond = g.material(R"({"normalTexture":{"index":)" + index + R"(,"texCoord":1}})");
    const int onFirst = g.material(R"({"normalTexture":{"index":)" + index + "}}");
    const int byTransform = g.material(R"({"normalTexture":{"index":)" + index +
                                       R"(,"extensions":{"KHR_texture_transform":{"texCoord":1}}}})");
    g.extensionsUsed = {"KHR_texture_transform"};
    for (const int material : {onSecond, onFirst, byTransform}) {
        const int uv1 = g.accessor<float>({0, 0, 0, 1, 1, 1, 1, 0}, 5126, "VEC2", 4);
        g.primitive(g.quadAttributes(0, 0, 1, 1, 0, 0, 0, 1, 1) + R"(,"TEXCOORD_1":)" + std::to_string(uv1), material);
    }
    const GltfModel model = loadGltfModel(g.save(dir, "tangents"));
    ASSERT_EQ(model.primitives.size(), 3u);
    const std::array<glm::vec4, 3> expected{glm::vec4(0, -1, 0, -1), glm::vec4(1, 0, 0, 1), glm::vec4(0, -1, 0, -1)};
    for (size_t p = 0; p < 3; ++p) {
        ASSERT_EQ(model.primitives[p].tangents.size(), 4u);
        for (const glm::vec4& t : model.primitives[p].tangents) {
            EXPECT_NEAR(glm::distance(glm::vec3(t), glm::vec3(expected[p])), 0.0f, 1e-5f) << "primitive " << p;
            EXPECT_EQ(t.w, expected[p].w) << "primitive " << p;
        }
    }
}

} // namespace
} // namespace lumar
