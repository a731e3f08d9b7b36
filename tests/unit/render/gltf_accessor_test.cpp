// Hand-written glTF files exercising the accessor reader and the scene walk: strides,
// normalized integers, sparse accessors, strips and fans, missing indices and normals, the
// node hierarchy, and the material fields. Expected values are worked out by hand here.
#include <cmath>
#include <string>

#include <glm/gtc/matrix_transform.hpp>
#include <gtest/gtest.h>

#include "gles_renderer/assets/gltf_model.h"
#include "mini_gltf.h"
#include "render_test_support.h"

namespace lumar {
namespace {

using test::MiniGltf;
using test::oneTriangle;
using test::ScratchDir;

// A 2x1 quad strip: vertices (0,0) (0,1) (1,0) (1,1) in the xy-plane, not indexed.
MiniGltf fourVertices(int mode)
{
    MiniGltf g;
    g.add<float>({0, 0, 0, 0, 1, 0, 1, 0, 0, 1, 1, 0});
    g.bufferViews = R"({"buffer":0,"byteLength":48})";
    g.accessors = R"({"bufferView":0,"componentType":5126,"count":4,"type":"VEC3"})";
    g.meshes = R"({"primitives":[{"attributes":{"POSITION":0},"mode":)" + std::to_string(mode) + "}]}";
    return g;
}

TEST(GltfAccessors, NonIndexedTrianglesGetSequentialIndicesAndGeneratedNormals)
{
    ScratchDir dir;
    MiniGltf g = oneTriangle();
    g.meshes = R"({"primitives":[{"attributes":{"POSITION":0}}]})";
    const GltfModel model = loadGltfModel(g.write(dir, "plain"));
    ASSERT_EQ(model.primitives.size(), 1u);
    const GltfPrimitive& p = model.primitives[0];
    EXPECT_EQ(p.indices, (std::vector<uint32_t>{0, 1, 2}));
    EXPECT_EQ(p.material, -1);
    for (const glm::vec3& n : p.normals) {
        EXPECT_NEAR(glm::distance(n, glm::vec3(0, 0, 1)), 0.0f, 1e-6f); // counter-clockwise seen from +z
    }
    for (const glm::vec2& uv : p.uvs) {
        EXPECT_EQ(uv, glm::vec2(0.0f));
    }
}

TEST(GltfAccessors, StripsAndFansBecomeTriangleListsWithTheSpecifiedWinding)
{
    ScratchDir dir;
    // glTF 2.0 §3.7.2.1: strip triangle i = {i, i+1+i%2, i+2-i%2}; fan = {i+1, i+2, 0}.
    const GltfModel strip = loadGltfModel(fourVertices(5).write(dir, "strip"));
    EXPECT_EQ(strip.primitives.at(0).indices, (std::vector<uint32_t>{0, 1, 2, 1, 3, 2}));
    const GltfModel fan = loadGltfModel(fourVertices(6).write(dir, "fan"));
    EXPECT_EQ(fan.primitives.at(0).indices, (std::vector<uint32_t>{1, 2, 0, 2, 3, 0}));
    // Lines are skipped (with a warning), leaving a model with no triangles.
    EXPECT_THROW((void)loadGltfModel(fourVertices(1).write(dir, "lines")), InputError);
}

TEST(GltfAccessors, InterleavedStrideNormalizedUvsAndByteIndices)
{
    ScratchDir dir;
    MiniGltf g;
    // Interleaved per vertex: position (3 floats) then normal (3 floats) = 24-byte stride.
    g.add<float>({0, 0, 0, 0, 0, 2, 1, 0, 0, 0, 0, 3, 0, 1, 0, 0, 0, 4});
    const size_t uvs = g.add<uint16_t>({0, 65535, 65535, 32768, 0, 0});
    const size_t indices = g.add<uint8_t>({2, 0, 1});
    g.bufferViews = R"({"buffer":0,"byteLength":72,"byteStride":24},)"
                    R"({"buffer":0,"byteOffset":)" +
                    std::to_string(uvs) +
                    R"(,"byteLength":12},)"
                    R"({"buffer":0,"byteOffset":)" +
                    std::to_string(indices) + R"(,"byteLength":3})";
    g.accessors = R"({"bufferView":0,"componentType":5126,"count":3,"type":"VEC3"},)"
                  R"({"bufferView":0,"byteOffset":12,"componentType":5126,"count":3,"type":"VEC3"},)"
                  R"({"bufferView":1,"componentType":5123,"normalized":true,"count":3,"type":"VEC2"},)"
                  R"({"bufferView":2,"componentType":5121,"count":3,"type":"SCALAR"})";
    g.meshes = R"({"primitives":[{"attributes":{"POSITION":0,"NORMAL":1,"TEXCOORD_0":2},"indices":3}]})";
    const GltfModel model = loadGltfModel(g.write(dir, "interleaved"));
    const GltfPrimitive& p = model.primitives.at(0);
    EXPECT_EQ(p.positions.at(1), glm::vec3(1, 0, 0));
    EXPECT_EQ(p.positions.at(2), glm::vec3(0, 1, 0));
    for (const glm::vec3& n : p.normals) {
        EXPECT_EQ(n, glm::vec3(0, 0, 1)); // the file's (0,0,2..4), normalised
    }
    EXPECT_EQ(p.uvs.at(0), glm::vec2(0.0f, 1.0f));
    EXPECT_EQ(p.uvs.at(1), glm::vec2(1.0f, 32768.0f / 65535.0f));
    EXPECT_EQ(p.indices, (std::vector<uint32_t>{2, 0, 1}));
}

TEST(GltfAccessors, SparseValuesReplaceDenseOnes)
{
    ScratchDir dir;
    MiniGltf g = oneTriangle();
    const size_t sparseIndices = g.add<uint16_t>({2});
    const size_t sparseValues = g.add<float>({0, 5, 0});
    g.bufferViews += R"(,{"buffer":0,"byteOffset":)" + std::to_string(sparseIndices) + R"(,"byteLength":2})";
    g.bufferViews += R"(,{"buffer":0,"byteOffset":)" + std::to_string(sparseValues) + R"(,"byteLength":12})";
    g.accessors = R"({"bufferView":0,"componentType":5126,"count":3,"type":"VEC3","sparse":{"count":1,)"
                  R"("indices":{"bufferView":2,"componentType":5123},"values":{"bufferView":3}}},)"
                  R"({"bufferView":1,"componentType":5123,"count":3,"type":"SCALAR"})";
    const GltfModel model = loadGltfModel(g.write(dir, "sparse"));
    const GltfPrimitive& p = model.primitives.at(0);
    EXPECT_EQ(p.positions.at(0), glm::vec3(0, 0, 0));
    EXPECT_EQ(p.positions.at(1), glm::vec3(1, 0, 0));
    EXPECT_EQ(p.positions.at(2), glm::vec3(0, 5, 0));
    EXPECT_EQ(model.boundsMax, glm::vec3(1, 5, 0));
}

TEST(GltfAccessors, NodeTransformsComposeDownTheHierarchy)
{
    ScratchDir dir;
    MiniGltf g = oneTriangle();
    // Parent: translation (1,2,3). Child: rotation 90 degrees about +z (quaternion x,y,z,w),
    // scale 2. A third node instances the mesh again through a column-major matrix.
    const double h = std::sqrt(0.5);
    g.nodes = R"({"translation":[1,2,3],"children":[1,2]},)"
              R"({"mesh":0,"rotation":[0,0,)" +
              std::to_string(h) + "," + std::to_string(h) +
              R"(],"scale":[2,2,2]},)"
              R"({"mesh":0,"matrix":[1,0,0,0, 0,1,0,0, 0,0,1,0, 10,0,0,1]})";
    const GltfModel model = loadGltfModel(g.write(dir, "hierarchy"));
    ASSERT_EQ(model.primitives.size(), 2u);
    EXPECT_EQ(model.triangleCount(), 2u);

    // Independent expectation: glm's own TRS, and the points worked out by hand.
    const glm::mat4 expectedChild = glm::translate(glm::mat4(1.0f), glm::vec3(1, 2, 3)) *
                                    glm::rotate(glm::mat4(1.0f), glm::radians(90.0f), glm::vec3(0, 0, 1)) *
                                    glm::scale(glm::mat4(1.0f), glm::vec3(2.0f));
    for (int c = 0; c < 4; ++c) {
        for (int r = 0; r < 4; ++r) {
            EXPECT_NEAR(model.primitives[0].modelFromMesh[c][r], expectedChild[c][r], 1e-5f);
        }
    }
    // (1,0,0) -> rotate -> (0,1,0) -> scale -> (0,2,0) -> translate -> (1,4,3).
    const glm::vec3 moved = glm::vec3(model.primitives[0].modelFromMesh * glm::vec4(1, 0, 0, 1));
    EXPECT_NEAR(glm::distance(moved, glm::vec3(1, 4, 3)), 0.0f, 1e-5f);
    // Second instance: translation (1,2,3) then (10,0,0); its vertices span x 11..12.
    EXPECT_NEAR(model.boundsMax.x, 12.0f, 1e-5f);
    EXPECT_NEAR(model.boundsMin.x, -1.0f, 1e-5f); // (0,1,0) -> (-2,0,0) scaled/rotated -> x = 1 - 2
    EXPECT_NEAR(model.boundsMin.y, 2.0f, 1e-5f);
    EXPECT_NEAR(model.boundsMax.y, 4.0f, 1e-5f);
    EXPECT_NEAR(model.boundsMin.z, 3.0f, 1e-5f);
    EXPECT_NEAR(model.boundsMax.z, 3.0f, 1e-5f);
}

TEST(GltfAccessors, MaterialFieldsAndOneImageAsColourAndAsData)
{
    ScratchDir dir;
    std::filesystem::copy_file(test::testDataPath("apriltag/tag36h11/tag36_11_00000.png"), dir.file("tag.png"));
    MiniGltf g = oneTriangle();
    g.meshes = R"({"primitives":[{"attributes":{"POSITION":0},"indices":1,"material":0}]})";
    g.materials = R"({"name":"glowing","doubleSided":true,"emissiveFactor":[1,0.5,0],)"
                  R"("extensions":{"KHR_materials_emissive_strength":{"emissiveStrength":4}},)"
                  R"("normalTexture":{"index":0,"scale":0.5},"emissiveTexture":{"index":0},)"
                  R"("pbrMetallicRoughness":{"baseColorFactor":[0.5,0.25,1,0.75],"metallicFactor":0.3,)"
                  R"("roughnessFactor":0.7,"baseColorTexture":{"index":0}}})";
    g.extra = R"(,"extensionsUsed":["KHR_materials_emissive_strength"],)"
              R"("images":[{"uri":"tag.png"}],"textures":[{"source":0}])";
    const GltfModel model = loadGltfModel(g.write(dir, "material"));
    ASSERT_EQ(model.materials.size(), 1u);
    const GltfMaterial& m = model.materials[0];
    EXPECT_EQ(m.name, "glowing");
    EXPECT_TRUE(m.doubleSided);
    EXPECT_EQ(m.baseColorFactor, glm::vec4(0.5f, 0.25f, 1.0f, 0.75f));
    EXPECT_FLOAT_EQ(m.metallicFactor, 0.3f);
    EXPECT_FLOAT_EQ(m.roughnessFactor, 0.7f);
    EXPECT_EQ(m.emissiveFactor, glm::vec3(4.0f, 2.0f, 0.0f)); // factor x emissiveStrength
    EXPECT_FLOAT_EQ(m.normalScale, 0.5f);
    EXPECT_EQ(m.metallicRoughnessTexture, -1);
    // One image, used as sRGB colour (base colour, emissive) and as linear data (normals).
    ASSERT_EQ(model.textures.size(), 2u);
    ASSERT_GE(m.baseColorTexture, 0);
    EXPECT_EQ(m.emissiveTexture, m.baseColorTexture);
    ASSERT_GE(m.normalTexture, 0);
    EXPECT_NE(m.normalTexture, m.baseColorTexture);
    EXPECT_TRUE(model.textures[size_t(m.baseColorTexture)].srgb);
    EXPECT_FALSE(model.textures[size_t(m.normalTexture)].srgb);
    const Image8& image = model.textures[size_t(m.baseColorTexture)].image;
    ASSERT_EQ(image.width, 10); // the tag PNG: 10 x 10 RGBA, white 1-px border, black ring
    ASSERT_EQ(image.height, 10);
    EXPECT_EQ(image.at(0, 0)[0], 255);
    EXPECT_EQ(image.at(1, 1)[0], 0);
    EXPECT_EQ(image.at(1, 1)[3], 255);
}

TEST(GltfAccessors, MissingExternalImageDropsTheTextureWithAWarning)
{
    ScratchDir dir;
    MiniGltf g = oneTriangle();
    g.materials = R"({"pbrMetallicRoughness":{"baseColorTexture":{"index":0}}})";
    g.extra = R"(,"images":[{"uri":"absent.png"}],"textures":[{"source":0}])";
    const GltfModel model = loadGltfModel(g.write(dir, "absent-image"));
    EXPECT_TRUE(model.textures.empty());
    EXPECT_EQ(model.materials.at(0).baseColorTexture, -1);
}

} // namespace
} // namespace lumar
