// Khronos glTF sample models (tests/data/khronos, MANIFEST.md there): each one loads, and the
// feature it demonstrates is checked numerically, from the rendered image where the renderer
// draws that feature, from the loaded data otherwise. Draco and meshopt are checked in full:
// the Draco Box renders as the plain Box, the Draco RiggedSimple holds the plain one's
// triangles, joints and weights within Draco's quantisation.
#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <set>
#include <string>
#include <vector>

#include <glm/gtc/matrix_transform.hpp>
#include <gtest/gtest.h>
#include <tiny_gltf.h>

#include "gl_test_support.h"
#include "gles_renderer/assets/gltf_compression.h"
#include "gles_renderer/assets/gltf_parse.h"

namespace lumar {
namespace {

std::filesystem::path sample(const std::string& relative)
{
    return std::filesystem::path(LUMAR_TEST_DATA_DIR) / "khronos" / relative;
}

// The values of any (non-sparse) accessor of a parsed model as doubles, `components` per
// element (the test's own reader: integers of every width, unnormalised).
std::vector<double> rawValues(const tinygltf::Model& model, int accessorIndex)
{
    const tinygltf::Accessor& accessor = model.accessors.at(size_t(accessorIndex));
    const tinygltf::BufferView& view = model.bufferViews.at(size_t(accessor.bufferView));
    const std::vector<unsigned char>& data = model.buffers.at(size_t(view.buffer)).data;
    const int components = tinygltf::GetNumComponentsInType(uint32_t(accessor.type));
    const int size = tinygltf::GetComponentSizeInBytes(uint32_t(accessor.componentType));
    const size_t stride = view.byteStride != 0 ? view.byteStride : size_t(components * size);
    std::vector<double> out;
    for (size_t i = 0; i < accessor.count; ++i) {
        for (int c = 0; c < components; ++c) {
            const size_t at = view.byteOffset + accessor.byteOffset + i * stride + size_t(c * size);
            EXPECT_LE(at + size_t(size), data.size());
            const unsigned char* p = data.data() + at;
            double v = 0;
            switch (accessor.componentType) {
            case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE:
                v = p[0];
                break;
            case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT:
                v = p[0] | p[1] << 8;
                break;
            case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT:
                v = double(uint32_t(p[0] | p[1] << 8 | p[2] << 16) | uint32_t(p[3]) << 24);
                break;
            default: {
                float f;
                std::memcpy(&f, p, 4);
                v = f;
            }
            }
            out.push_back(v);
        }
    }
    return out;
}

int attribute(const tinygltf::Model& model, const std::string& name, size_t mesh = 0)
{
    const auto& attributes = model.meshes.at(mesh).primitives.at(0).attributes;
    const auto found = attributes.find(name);
    return found == attributes.end() ? -1 : found->second;
}

struct Expected {
    const char* file;
    size_t primitives;
    size_t triangles;
};

// Counted from the files' JSON (scene graph walked, every node instance, triangles only).
constexpr Expected kSamples[] = {
    {"Box/Box.glb", 1, 12},
    {"Box/Draco/Box.gltf", 1, 12},
    {"Box/Draco/BoxDraco.glb", 1, 12},
    {"BoxVertexColors/BoxVertexColors.glb", 1, 12},
    {"VertexColorTest/VertexColorTest.glb", 2, 36},
    {"MultiUVTest/MultiUVTest.glb", 1, 12},
    {"TextureSettingsTest/TextureSettingsTest.glb", 10, 72},
    {"TextureTransformTest/TextureTransformTest.gltf", 12, 24},
    {"SimpleMorph/SimpleMorph.gltf", 1, 1},
    {"SimpleSkin/SimpleSkin.gltf", 1, 8},
    {"RiggedSimple/RiggedSimple.glb", 1, 188},
    {"RiggedSimple/Draco/RiggedSimple.gltf", 1, 188},
};

TEST(KhronosSamples, EveryChosenModelLoadsWithItsTriangles)
{
    for (const Expected& e : kSamples) {
        SCOPED_TRACE(e.file);
        if (!gltf::dracoDecoderBuilt() && std::string(e.file).find("Draco") != std::string::npos) {
            continue;
        }
        const GltfModel model = loadGltfModel(sample(e.file));
        EXPECT_EQ(model.primitives.size(), e.primitives);
        EXPECT_EQ(model.triangleCount(), e.triangles);
        for (const GltfPrimitive& p : model.primitives) {
            EXPECT_EQ(p.normals.size(), p.positions.size());
            EXPECT_EQ(p.uvs.size(), p.positions.size());
        }
    }
}

// Draco: rendered, the decoded Box and the plain one are the same picture.
TEST(KhronosSamples, DracoBoxRendersAsThePlainBox)
{
    if (!gltf::dracoDecoderBuilt()) {
        GTEST_SKIP() << "built without Draco (LUMAR_WITH_DRACO)";
    }
    constexpr int kWidth = 320, kHeight = 240;
    LUMAR_RENDERER_OR_SKIP(renderer, kWidth, kHeight);
    renderer.setEnvironment(test::uniformEnvironment(0.8f), 1.0f);
    const CameraIntrinsics k = test::makeIntrinsics(kWidth, kHeight, 300, 300, 160, 120);
    const Image8 background = test::solidImage(kWidth, kHeight, 10, 20, 30);
    glm::dmat4 cameraFromModel = test::translation(0, 0, 4);
    cameraFromModel = glm::rotate(cameraFromModel, glm::radians(150.0), glm::dvec3(1, 0, 0));
    cameraFromModel = glm::rotate(cameraFromModel, glm::radians(35.0), glm::dvec3(0, 1, 0));

    std::array<Image8, 2> images;
    const std::array<const char*, 2> files = {"Box/Box.glb", "Box/Draco/Box.gltf"};
    for (size_t i = 0; i < 2; ++i) {
        const ModelId id = renderer.addModel(loadGltfModel(sample(files[i])));
        const DrawItem item{id, cameraFromModel};
        renderer.render(background, k, {&item, 1});
        renderer.readback(images[i]);
    }
    size_t covered = 0, differing = 0;
    for (int y = 0; y < kHeight; ++y) {
        for (int x = 0; x < kWidth; ++x) {
            const uint8_t* a = images[0].at(x, y);
            const uint8_t* b = images[1].at(x, y);
            const uint8_t* bg = background.at(x, y);
            covered += a[0] != bg[0] || a[1] != bg[1] || a[2] != bg[2];
            differing += std::abs(a[0] - b[0]) > 8 || std::abs(a[1] - b[1]) > 8 || std::abs(a[2] - b[2]) > 8;
        }
    }
    EXPECT_GT(covered, size_t(kWidth * kHeight / 20)) << "the box should be in view";
    // Draco's quantisation moves edges by a fraction of a pixel at most.
    EXPECT_LT(differing, covered / 100 + 10) << covered << " box pixels";
}

struct Corner {
    glm::vec3 position, normal;
};

std::vector<std::array<Corner, 3>> trianglesOf(const GltfModel& model)
{
    std::vector<std::array<Corner, 3>> triangles;
    for (const GltfPrimitive& p : model.primitives) {
        for (size_t i = 0; i + 2 < p.indices.size(); i += 3) {
            std::array<Corner, 3> t;
            for (size_t c = 0; c < 3; ++c) {
                t[c] = {p.positions[p.indices[i + c]], p.normals[p.indices[i + c]]};
            }
            triangles.push_back(t);
        }
    }
    return triangles;
}

// Draco (skinned model): the decoded RiggedSimple has the plain one's triangles (winding
// kept) and, vertex by vertex, its joints exactly and its weights within quantisation.
TEST(KhronosSamples, DracoRiggedSimpleMatchesThePlainOne)
{
    if (!gltf::dracoDecoderBuilt()) {
        GTEST_SKIP() << "built without Draco (LUMAR_WITH_DRACO)";
    }
    const GltfModel plain = loadGltfModel(sample("RiggedSimple/RiggedSimple.glb"));
    const GltfModel draco = loadGltfModel(sample("RiggedSimple/Draco/RiggedSimple.gltf"));
    // Positions quantised to 11 bits over the model's 9.15 m (half a step per axis: 2.2 mm,
    // 3.4 mm seen in length), normals to a few hundredths.
    constexpr float kPosition = 5e-3f, kNormal = 5e-2f;
    std::vector<std::array<Corner, 3>> got = trianglesOf(draco);
    const auto near = [&](const Corner& a, const Corner& b) {
        return glm::length(a.position - b.position) < kPosition && glm::length(a.normal - b.normal) < kNormal;
    };
    for (const auto& t : trianglesOf(plain)) {
        const auto match = std::find_if(got.begin(), got.end(), [&](const std::array<Corner, 3>& g) {
            for (size_t shift = 0; shift < 3; ++shift) {
                if (near(g[0], t[shift]) && near(g[1], t[(shift + 1) % 3]) && near(g[2], t[(shift + 2) % 3])) {
                    return true;
                }
            }
            return false;
        });
        ASSERT_NE(match, got.end()) << "a triangle of the plain model is missing";
        got.erase(match);
    }

    const tinygltf::Model plainData = gltf::parseGltfFile(sample("RiggedSimple/RiggedSimple.glb"));
    const tinygltf::Model dracoData = gltf::parseGltfFile(sample("RiggedSimple/Draco/RiggedSimple.gltf"));
    const std::vector<double> plainPositions = rawValues(plainData, attribute(plainData, "POSITION"));
    const std::vector<double> plainJoints = rawValues(plainData, attribute(plainData, "JOINTS_0"));
    const std::vector<double> plainWeights = rawValues(plainData, attribute(plainData, "WEIGHTS_0"));
    const std::vector<double> positions = rawValues(dracoData, attribute(dracoData, "POSITION"));
    const std::vector<double> joints = rawValues(dracoData, attribute(dracoData, "JOINTS_0"));
    const std::vector<double> weights = rawValues(dracoData, attribute(dracoData, "WEIGHTS_0"));
    ASSERT_EQ(joints.size(), positions.size() / 3 * 4);
    ASSERT_EQ(weights.size(), joints.size());
    for (size_t v = 0; v < positions.size() / 3; ++v) {
        // The plain vertex at the same place (positions coincide only across seams, where the
        // skinning data agrees too).
        size_t best = 0;
        double bestDistance = 1e30;
        for (size_t u = 0; u < plainPositions.size() / 3; ++u) {
            double d = 0;
            for (size_t c = 0; c < 3; ++c) {
                d += std::pow(positions[3 * v + c] - plainPositions[3 * u + c], 2);
            }
            if (d < bestDistance) {
                bestDistance = d;
                best = u;
            }
        }
        ASSERT_LT(std::sqrt(bestDistance), kPosition) << "vertex " << v;
        for (size_t c = 0; c < 4; ++c) {
            // An unused influence (weight 0) may name any joint.
            if (plainWeights[4 * best + c] > 0) {
                EXPECT_EQ(joints[4 * v + c], plainJoints[4 * best + c]) << "vertex " << v;
            }
            EXPECT_NEAR(weights[4 * v + c], plainWeights[4 * best + c], 2e-3) << "vertex " << v;
        }
    }
}

// Vertex colours (COLOR_0): the data the renderer draws with is read (drawn:
// khronos_render_test.cpp, VertexColorTest).
TEST(KhronosSamples, VertexColourSamplesCarryTheirColours)
{
    const tinygltf::Model box = gltf::parseGltfFile(sample("BoxVertexColors/BoxVertexColors.glb"));
    const std::vector<double> colours = rawValues(box, attribute(box, "COLOR_0"));
    ASSERT_EQ(colours.size(), 24u * 3u);
    std::set<std::array<double, 3>> distinct;
    for (size_t i = 0; i < colours.size(); i += 3) {
        distinct.insert({colours[i], colours[i + 1], colours[i + 2]});
        for (size_t c = 0; c < 3; ++c) {
            EXPECT_GE(colours[i + c], 0.0);
            EXPECT_LE(colours[i + c], 1.0);
        }
    }
    EXPECT_GE(distinct.size(), 6u) << "the box's corners are coloured differently";

    const tinygltf::Model test = gltf::parseGltfFile(sample("VertexColorTest/VertexColorTest.glb"));
    EXPECT_EQ(attribute(test, "COLOR_0", 0), -1);
    const std::vector<double> rgba = rawValues(test, attribute(test, "COLOR_0", 1));
    ASSERT_EQ(rgba.size(), 48u * 4u);
    std::set<std::array<double, 3>> checks;
    for (size_t i = 0; i < rgba.size(); i += 4) {
        checks.insert({rgba[i], rgba[i + 1], rgba[i + 2]});
    }
    EXPECT_GE(checks.size(), 3u) << "the colour checks have several colours";
}

// A second UV set (TEXCOORD_1), used by MultiUVTest's emissive texture.
TEST(KhronosSamples, MultiUvTestHasASecondUvSetItsEmissiveTextureUses)
{
    const tinygltf::Model model = gltf::parseGltfFile(sample("MultiUVTest/MultiUVTest.glb"));
    ASSERT_EQ(model.materials.size(), 1u);
    EXPECT_EQ(model.materials[0].emissiveTexture.texCoord, 1);
    EXPECT_EQ(model.materials[0].pbrMetallicRoughness.baseColorTexture.texCoord, 0);
    const std::vector<double> uv0 = rawValues(model, attribute(model, "TEXCOORD_0"));
    const std::vector<double> uv1 = rawValues(model, attribute(model, "TEXCOORD_1"));
    ASSERT_EQ(uv0.size(), uv1.size());
    EXPECT_LE(*std::max_element(uv1.begin(), uv1.end()), 0.25 + 1e-6);
    EXPECT_GT(*std::max_element(uv0.begin(), uv0.end()), 0.7);
    // The loaded first set is the file's TEXCOORD_0.
    const GltfModel loaded = loadGltfModel(sample("MultiUVTest/MultiUVTest.glb"));
    ASSERT_EQ(loaded.primitives[0].uvs.size(), uv0.size() / 2);
    for (size_t i = 0; i < loaded.primitives[0].uvs.size(); ++i) {
        EXPECT_FLOAT_EQ(loaded.primitives[0].uvs[i].x, float(uv0[2 * i]));
    }
}

// Samplers: TextureSettingsTest's quads reach outside [0, 1] in uv, where repeat, clamp and
// mirrored repeat differ; the file asks for all three.
TEST(KhronosSamples, TextureSettingsTestUsesEveryWrapModeOutsideTheUnitSquare)
{
    const tinygltf::Model model = gltf::parseGltfFile(sample("TextureSettingsTest/TextureSettingsTest.glb"));
    std::set<int> wraps;
    for (const tinygltf::Sampler& s : model.samplers) {
        wraps.insert(s.wrapS);
        wraps.insert(s.wrapT);
    }
    EXPECT_EQ(wraps, (std::set<int>{TINYGLTF_TEXTURE_WRAP_REPEAT, TINYGLTF_TEXTURE_WRAP_CLAMP_TO_EDGE,
                                    TINYGLTF_TEXTURE_WRAP_MIRRORED_REPEAT}));
    const GltfModel loaded = loadGltfModel(sample("TextureSettingsTest/TextureSettingsTest.glb"));
    size_t outside = 0;
    for (const GltfPrimitive& p : loaded.primitives) {
        for (const glm::vec2& uv : p.uvs) {
            outside += uv.x < 0 || uv.x > 1 || uv.y < 0 || uv.y > 1;
        }
    }
    EXPECT_GT(outside, 8u);
}

// Texture transforms: offsets and a rotation per material (KHR_texture_transform, used).
TEST(KhronosSamples, TextureTransformTestCarriesItsTransforms)
{
    const tinygltf::Model model = gltf::parseGltfFile(sample("TextureTransformTest/TextureTransformTest.gltf"));
    size_t transformed = 0;
    for (const tinygltf::Material& m : model.materials) {
        transformed += m.pbrMetallicRoughness.baseColorTexture.extensions.count("KHR_texture_transform");
    }
    EXPECT_GE(transformed, 6u);
}

// Morph targets: SimpleMorph's two targets and default weights 0.5, 0.5; its animation
// drives the weights (drawn at the keyframes: khronos_render_test.cpp).
TEST(KhronosSamples, SimpleMorphHasTwoTargetsAndAnimatedWeights)
{
    const tinygltf::Model model = gltf::parseGltfFile(sample("SimpleMorph/SimpleMorph.gltf"));
    ASSERT_EQ(model.meshes.size(), 1u);
    EXPECT_EQ(model.meshes[0].primitives[0].targets.size(), 2u);
    EXPECT_EQ(model.meshes[0].weights, (std::vector<double>{0.5, 0.5}));
    ASSERT_EQ(model.animations.size(), 1u);
    EXPECT_EQ(model.animations[0].channels[0].target_path, "weights");
}

// Skins: SimpleSkin's two joints, their inverse bind matrices, and the rotation animating
// joint node 2 (drawn bent at 0.5, 1 and 4 s: khronos_render_test.cpp).
TEST(KhronosSamples, SimpleSkinHasTwoJointsAndARotatingOne)
{
    const tinygltf::Model model = gltf::parseGltfFile(sample("SimpleSkin/SimpleSkin.gltf"));
    ASSERT_EQ(model.skins.size(), 1u);
    EXPECT_EQ(model.skins[0].joints, (std::vector<int>{1, 2}));
    EXPECT_EQ(rawValues(model, model.skins[0].inverseBindMatrices).size(), 32u);
    ASSERT_EQ(model.animations.size(), 1u);
    EXPECT_EQ(model.animations[0].channels[0].target_node, 2);
    EXPECT_EQ(model.animations[0].channels[0].target_path, "rotation");
}

// Instancing: SimpleInstancing's one node carries 125 instances (EXT_mesh_gpu_instancing).
TEST(KhronosSamples, SimpleInstancingDrawsEveryInstance)
{
    const tinygltf::Model model = gltf::parseGltfFile(sample("SimpleInstancing/SimpleInstancing.glb"));
    ASSERT_EQ(model.nodes.size(), 1u);
    const tinygltf::Value& instancing = model.nodes[0].extensions.at("EXT_mesh_gpu_instancing");
    const int translations = instancing.Get("attributes").Get("TRANSLATION").GetNumberAsInt();
    EXPECT_EQ(model.accessors.at(size_t(translations)).count, 125u);
    const GltfModel loaded = loadGltfModel(sample("SimpleInstancing/SimpleInstancing.glb"));
    EXPECT_EQ(loaded.triangleCount(), 125u * 12u);
    EXPECT_EQ(loaded.primitives.size(), 125u) << "one copy of the cube per instance";
}

} // namespace
} // namespace lumar
