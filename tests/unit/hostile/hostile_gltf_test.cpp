// glTF files built to hurt (issue 16): deep JSON, counts that claim data the file does not
// hold, instancing that multiplies a mesh, numbers beyond float, uris that leave the folder.
#include <filesystem>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "gles_renderer/assets/gltf_model.h"
#include "hostile_support.h"
#include "unit/render/mini_gltf.h"
#include "unit/render/render_test_support.h"

namespace lumar::test {
namespace {

std::string expectModelRejected(const std::filesystem::path& file, const std::string& detail)
{
    return expectRejected([&] { (void)loadGltfModel(file); }, file.string() + ": ", detail);
}

TEST(HostileGltf, DeeplyNestedExtrasAreRefusedBeforeTinygltf)
{
    const ScratchDir dir;
    MiniGltf g = oneTriangle();
    g.extra = R"(,"extras":)" + repeat(R"({"a":)", 5000) + "1" + repeat("}", 5000);
    expectModelRejected(g.write(dir, "deep_object"), "nested deeper than 64 levels");
    g.extra = R"(,"extras":)" + repeat("[", 100000) + repeat("]", 100000);
    expectModelRejected(g.write(dir, "deep_array"), "nested deeper than 64 levels");
    g.extra = R"(,"extras":)" + repeat(R"({"a":)", 40) + "1" + repeat("}", 40);
    EXPECT_NO_THROW((void)loadGltfModel(g.write(dir, "fine")));
}

TEST(HostileGltf, SparseAccessorCannotClaimDataTheFileDoesNotHold)
{
    const ScratchDir dir;
    MiniGltf g;
    const size_t index = g.add<uint32_t>({0});
    const size_t value = g.add<float>({1, 2, 3});
    g.bufferViews = R"({"buffer":0,"byteOffset":)" + std::to_string(index) + R"(,"byteLength":4},)" +
                    R"({"buffer":0,"byteOffset":)" + std::to_string(value) + R"(,"byteLength":12})";
    g.accessors = R"({"componentType":5126,"count":16000000,"type":"VEC3","sparse":{"count":1,)"
                  R"("indices":{"bufferView":0,"componentType":5125},"values":{"bufferView":1}}})";
    g.meshes = R"({"primitives":[{"attributes":{"POSITION":0}}]})";
    g.nodes = repeat(R"({"mesh":0},)", 7) + R"({"mesh":0})";
    expectModelRejected(g.write(dir, "sparse"), "more than the file's buffers hold");
}

TEST(HostileGltf, InstancesCannotMultiplyAMeshPastTheSceneBudget)
{
    const ScratchDir dir;
    MiniGltf g;
    // A strip of 700,000 one-byte indices is 699,998 triangles; eight nodes draw it 8 times.
    const size_t positions = g.add<float>({0, 0, 0, 1, 0, 0, 0, 1, 0});
    std::vector<uint8_t> strip(700000);
    for (size_t i = 0; i < strip.size(); ++i)
        strip[i] = uint8_t(i % 3);
    const size_t indices = g.bin.size();
    g.bin.insert(g.bin.end(), strip.begin(), strip.end());
    g.bufferViews = R"({"buffer":0,"byteOffset":)" + std::to_string(positions) + R"(,"byteLength":36},)" +
                    R"({"buffer":0,"byteOffset":)" + std::to_string(indices) + R"(,"byteLength":700000})";
    g.accessors = R"({"bufferView":0,"componentType":5126,"count":3,"type":"VEC3"},)"
                  R"({"bufferView":1,"componentType":5121,"count":700000,"type":"SCALAR"})";
    g.meshes = R"({"primitives":[{"attributes":{"POSITION":0},"indices":1,"mode":5}]})";
    g.nodes = R"({"children":[1,2,3,4,5,6,7,8]},)" + repeat(R"({"mesh":0},)", 7) + R"({"mesh":0})";
    expectModelRejected(g.write(dir, "instances"), "more than 4194304 triangles");
}

TEST(HostileGltf, FactorsMustBeFiniteAndInRange)
{
    const ScratchDir dir;
    MiniGltf g = oneTriangle();
    g.meshes = R"({"primitives":[{"attributes":{"POSITION":0},"indices":1,"material":0}]})";
    g.materials = R"({"pbrMetallicRoughness":{"baseColorFactor":[1e300,1,1,1]}})";
    expectModelRejected(g.write(dir, "base"), "outside [0, 1]");
    g.materials = R"({"emissiveFactor":[1,1,1e300]})";
    expectModelRejected(g.write(dir, "emissive"), "outside [0, 1]");
    g.materials = R"({"emissiveFactor":[1,1,1],"extensions":{"KHR_materials_emissive_strength":)"
                  R"({"emissiveStrength":1e300}}})";
    expectModelRejected(g.write(dir, "strength"), "emissiveStrength");
    g.materials = R"({"normalTexture":{"index":0,"scale":1e300}})";
    g.extra = R"(,"textures":[{}])";
    expectModelRejected(g.write(dir, "normal_scale"), "normalTexture.scale");
    g.extra.clear();
    g.materials = R"({"emissiveFactor":[0,0,0],"extensions":{"KHR_materials_emissive_strength":)"
                  R"({"emissiveStrength":5}}})";
    EXPECT_EQ(loadGltfModel(g.write(dir, "fine")).materials[0].emissiveFactor, glm::vec3(0.0f));
}

TEST(HostileGltf, NodeTransformBeyondFloatIsRefused)
{
    const ScratchDir dir;
    MiniGltf g = oneTriangle();
    g.nodes = R"({"mesh":0,"scale":[1e300,1,1]})";
    expectModelRejected(g.write(dir, "scale"), "beyond floating-point range");
}

// A model in dir/models/ whose buffer uri is `uri`; the buffer's bytes are also written to
// dir/secret.bin, outside the model's folder, as the file an attacker would want read.
std::filesystem::path modelWithBufferUri(const ScratchDir& dir, const std::string& uri)
{
    std::filesystem::create_directories(dir.file("models"));
    MiniGltf g = oneTriangle();
    writeBytes(dir.file("secret.bin"), g.bin);
    const std::string json = R"({"asset":{"version":"2.0"},"scene":0,"scenes":[{"nodes":[0]}],"buffers":[{"uri":")" +
                             uri + R"(","byteLength":)" + std::to_string(g.bin.size()) +
                             R"(}],"bufferViews":[{"buffer":0,"byteOffset":0,"byteLength":36},)"
                             R"({"buffer":0,"byteOffset":36,"byteLength":6}],"accessors":[)" +
                             g.accessors + R"(],"meshes":[)" + g.meshes + R"(],"nodes":[{"mesh":0}]})";
    const std::filesystem::path file = dir.file("models/model.gltf");
    writeText(file, json);
    return file;
}

TEST(HostileGltf, UrisStayInsideTheModelsFolder)
{
    const ScratchDir dir;
    expectModelRejected(modelWithBufferUri(dir, "../secret.bin"), "'..' is not allowed");
    expectModelRejected(modelWithBufferUri(dir, "../../../../etc/hostname"), "'..' is not allowed");
    expectModelRejected(modelWithBufferUri(dir, "%2e%2e/secret.bin"), "'..' is not allowed");
    expectModelRejected(modelWithBufferUri(dir, "sub/..\\\\..\\\\secret.bin"), "'..' is not allowed");
    expectModelRejected(modelWithBufferUri(dir, dir.file("secret.bin").string()), "absolute path");
    expectModelRejected(modelWithBufferUri(dir, "file://" + dir.file("secret.bin").string()), "URI scheme");
    expectModelRejected(modelWithBufferUri(dir, "file:secret.bin"), "URI scheme");
    expectModelRejected(modelWithBufferUri(dir, "http://example.com/x.bin"), "URI scheme");
    // A symbolic link inside the folder that points outside it is not followed.
    std::filesystem::create_symlink(dir.file("secret.bin"), dir.file("models/link.bin"));
    expectModelRejected(modelWithBufferUri(dir, "link.bin"), "link.bin");
    // Inside the folder: read.
    std::filesystem::copy_file(dir.file("secret.bin"), dir.file("models/inside.bin"));
    EXPECT_EQ(loadGltfModel(modelWithBufferUri(dir, "inside.bin")).triangleCount(), 1u);
    std::filesystem::create_directories(dir.file("models/sub"));
    std::filesystem::copy_file(dir.file("secret.bin"), dir.file("models/sub/in%20sub.bin"));
    EXPECT_EQ(loadGltfModel(modelWithBufferUri(dir, "sub/in%2520sub.bin")).triangleCount(), 1u);
}

TEST(HostileGltf, ImageUrisFollowTheSameRule)
{
    const ScratchDir dir;
    MiniGltf g = oneTriangle();
    g.extra = R"(,"images":[{"uri":"../../etc/hostname"}])";
    expectModelRejected(g.write(dir, "image"), "images[0].uri");
}

} // namespace
} // namespace lumar::test
