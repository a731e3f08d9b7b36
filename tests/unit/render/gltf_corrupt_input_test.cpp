// Corrupt, truncated and hostile glTF input: every case must end in an InputError whose one
// message line starts with the file's path; nothing may crash, hang or read out of bounds.
#include <cmath>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "gles_renderer/assets/gltf_model.h"
#include "mini_gltf.h"
#include "render_test_support.h"

namespace lumar {
namespace {

using test::expectInputErrorNamingFile;
using test::MiniGltf;
using test::oneTriangle;
using test::ScratchDir;

std::string expectRejected(const std::filesystem::path& file)
{
    return expectInputErrorNamingFile([&] { (void)loadGltfModel(file); }, file);
}

// For inputs that might be valid by chance (mutated bytes): loading either succeeds or
// throws a well-formed InputError.
void expectLoadsOrRejected(const std::filesystem::path& file)
{
    try {
        (void)loadGltfModel(file);
    } catch (const InputError&) {
        expectRejected(file);
    }
}

std::vector<uint8_t> boxTextured()
{
    return test::readBytes(test::testDataPath("models/BoxTextured.glb"));
}

TEST(GltfCorruptInput, MissingAndEmptyFiles)
{
    ScratchDir dir;
    EXPECT_NE(expectRejected(dir.file("absent.glb")).find("no such file"), std::string::npos);
    test::writeBytes(dir.file("empty.glb"), {});
    EXPECT_NE(expectRejected(dir.file("empty.glb")).find("empty"), std::string::npos);
    test::writeBytes(dir.file("empty.gltf"), {});
    expectRejected(dir.file("empty.gltf"));
}

TEST(GltfCorruptInput, TruncatedGlbAtManyLengths)
{
    ScratchDir dir;
    const std::vector<uint8_t> whole = boxTextured();
    ASSERT_EQ(whole.size(), 6540u); // MANIFEST §4
    for (const size_t length : {size_t(1), size_t(4), size_t(11), size_t(12), size_t(19), size_t(20), size_t(27),
                                size_t(100), size_t(1000), whole.size() / 2, whole.size() - 8, whole.size() - 1}) {
        SCOPED_TRACE("first " + std::to_string(length) + " bytes");
        const auto file = dir.file("truncated-" + std::to_string(length) + ".glb");
        test::writeBytes(file, std::vector<uint8_t>(whole.begin(), whole.begin() + std::ptrdiff_t(length)));
        expectRejected(file);
    }
}

TEST(GltfCorruptInput, RandomBytes)
{
    ScratchDir dir;
    std::mt19937 random(1234);
    for (const size_t length : {3u, 20u, 64u, 4096u}) {
        std::vector<uint8_t> bytes(length);
        for (uint8_t& b : bytes) {
            b = uint8_t(random());
        }
        for (const char* extension : {".glb", ".gltf"}) {
            const auto file = dir.file("random-" + std::to_string(length) + extension);
            test::writeBytes(file, bytes);
            expectRejected(file);
        }
        // The same bytes behind a valid GLB header: the chunk walk must refuse them.
        std::vector<uint8_t> withHeader = {'g', 'l', 'T', 'F', 2, 0, 0, 0};
        const uint32_t total = uint32_t(12 + bytes.size());
        withHeader.insert(withHeader.end(),
                          {uint8_t(total), uint8_t(total >> 8), uint8_t(total >> 16), uint8_t(total >> 24)});
        withHeader.insert(withHeader.end(), bytes.begin(), bytes.end());
        const auto file = dir.file("random-header-" + std::to_string(length) + ".glb");
        test::writeBytes(file, withHeader);
        expectRejected(file);
    }
}

// A deterministic mutation fuzz over BoxTextured: flipped bytes anywhere (JSON, binary chunk,
// the PNG) either still load or are rejected cleanly.
TEST(GltfCorruptInput, MutatedBoxTexturedNeverCrashes)
{
    ScratchDir dir;
    const std::vector<uint8_t> whole = boxTextured();
    std::mt19937 random(42);
    for (int round = 0; round < 300; ++round) {
        std::vector<uint8_t> bytes = whole;
        const int flips = 1 + int(random() % 8);
        for (int f = 0; f < flips; ++f) {
            bytes[random() % bytes.size()] = uint8_t(random());
        }
        const auto file = dir.file("mutated.glb");
        test::writeBytes(file, bytes);
        SCOPED_TRACE("round " + std::to_string(round));
        expectLoadsOrRejected(file);
    }
}

TEST(GltfCorruptInput, JsonSyntaxErrorAndMissingBuffer)
{
    ScratchDir dir;
    test::writeText(dir.file("syntax.gltf"), R"({"asset":{"version":"2.0"}, "nodes": [)");
    expectRejected(dir.file("syntax.gltf"));

    const auto file = oneTriangle().write(dir, "triangle");
    std::filesystem::remove(dir.file("triangle.bin"));
    expectRejected(file);
}

struct BrokenCase {
    const char* name;
    void (*breakIt)(MiniGltf&);
    const char* expectedInMessage;
};

const BrokenCase kBrokenCases[] = {
    {"index out of range",
     [](MiniGltf& g) {
         g.bin[36 + 4] = 7; // third u16 index: 2 -> 7, with 3 vertices
     },
     "index 7 is out of range"},
    {"accessor past the end of its bufferView",
     [](MiniGltf& g) {
         g.accessors = R"({"bufferView":0,"componentType":5126,"count":4,"type":"VEC3"},)"
                       R"({"bufferView":1,"componentType":5123,"count":3,"type":"SCALAR"})";
     },
     "run past the end of bufferView 0"},
    {"accessor offset past the end",
     [](MiniGltf& g) {
         g.accessors = R"({"bufferView":0,"byteOffset":4000000000,"componentType":5126,"count":3,"type":"VEC3"},)"
                       R"({"bufferView":1,"componentType":5123,"count":3,"type":"SCALAR"})";
     },
     "run past the end"},
    {"bufferView past the end of the buffer",
     [](MiniGltf& g) {
         g.bufferViews = R"({"buffer":0,"byteLength":36},{"buffer":0,"byteOffset":36,"byteLength":600})";
     },
     "lies outside its buffer"},
    {"bufferView of a buffer that does not exist",
     [](MiniGltf& g) { g.bufferViews = R"({"buffer":3,"byteLength":36},{"buffer":0,"byteOffset":36,"byteLength":6})"; },
     "buffer 3"},
    {"attribute accessor that does not exist",
     [](MiniGltf& g) { g.meshes = R"({"primitives":[{"attributes":{"POSITION":9},"indices":1}]})"; },
     "accessor 9 does not exist"},
    {"stride smaller than an element",
     [](MiniGltf& g) {
         g.bufferViews = R"({"buffer":0,"byteLength":36,"byteStride":8},{"buffer":0,"byteOffset":36,"byteLength":6})";
     },
     "byteStride 8"},
    {"float indices",
     [](MiniGltf& g) {
         g.accessors = R"({"bufferView":0,"componentType":5126,"count":3,"type":"VEC3"},)"
                       R"({"bufferView":0,"componentType":5126,"count":3,"type":"SCALAR"})";
     },
     "not an unsigned integer type"},
    {"positions as VEC2",
     [](MiniGltf& g) {
         g.accessors = R"({"bufferView":0,"componentType":5126,"count":3,"type":"VEC2"},)"
                       R"({"bufferView":1,"componentType":5123,"count":3,"type":"SCALAR"})";
     },
     "expected 3"},
    {"non-finite position",
     [](MiniGltf& g) {
         const float nan = std::numeric_limits<float>::quiet_NaN();
         std::memcpy(g.bin.data() + 4, &nan, 4);
     },
     "non-finite"},
    {"index count not a multiple of 3",
     [](MiniGltf& g) {
         g.accessors = R"({"bufferView":0,"componentType":5126,"count":3,"type":"VEC3"},)"
                       R"({"bufferView":1,"componentType":5123,"count":2,"type":"SCALAR"})";
     },
     "not a multiple of 3"},
    {"mesh that does not exist", [](MiniGltf& g) { g.nodes = R"({"mesh":5})"; }, "mesh 5 does not exist"},
    {"node cycle", [](MiniGltf& g) { g.nodes = R"({"mesh":0,"children":[1]},{"children":[0]})"; }, "not a tree"},
    {"child node that does not exist", [](MiniGltf& g) { g.nodes = R"({"mesh":0,"children":[8]})"; }, "node 8"},
    {"material that does not exist",
     [](MiniGltf& g) { g.meshes = R"({"primitives":[{"attributes":{"POSITION":0},"indices":1,"material":2}]})"; },
     "material 2 does not exist"},
    {"texture that does not exist",
     [](MiniGltf& g) { g.materials = R"({"pbrMetallicRoughness":{"baseColorTexture":{"index":4}}})"; },
     "texture 4 does not exist"},
    {"unsupported required extension",
     [](MiniGltf& g) {
         g.extra = R"(,"extensionsUsed":["KHR_texture_basisu"],"extensionsRequired":["KHR_texture_basisu"])";
     },
     "KHR_texture_basisu"}, // (Draco, named here before, is decoded now: gltf_compression_test.cpp)
    {"only points", [](MiniGltf& g) { g.meshes = R"({"primitives":[{"attributes":{"POSITION":0},"mode":0}]})"; },
     "no triangles"},
    {"sparse index out of range",
     [](MiniGltf& g) {
         const size_t indices = g.add<uint8_t>({5});
         const size_t values = g.add<float>({9, 9, 9});
         g.bufferViews += R"(,{"buffer":0,"byteOffset":)" + std::to_string(indices) + R"(,"byteLength":1})";
         g.bufferViews += R"(,{"buffer":0,"byteOffset":)" + std::to_string(values) + R"(,"byteLength":12})";
         g.accessors = R"({"bufferView":0,"componentType":5126,"count":3,"type":"VEC3","sparse":{"count":1,)"
                       R"("indices":{"bufferView":2,"componentType":5121},"values":{"bufferView":3}}},)"
                       R"({"bufferView":1,"componentType":5123,"count":3,"type":"SCALAR"})";
     },
     "index 5 is not below count 3"},
    {"huge count with no data behind it",
     [](MiniGltf& g) {
         const size_t indices = g.add<uint8_t>({0});
         const size_t values = g.add<float>({1, 1, 1});
         g.bufferViews += R"(,{"buffer":0,"byteOffset":)" + std::to_string(indices) + R"(,"byteLength":1})";
         g.bufferViews += R"(,{"buffer":0,"byteOffset":)" + std::to_string(values) + R"(,"byteLength":12})";
         g.accessors = R"({"componentType":5126,"count":4000000000,"type":"VEC3","sparse":{"count":1,)"
                       R"("indices":{"bufferView":2,"componentType":5121},"values":{"bufferView":3}}},)"
                       R"({"bufferView":1,"componentType":5123,"count":3,"type":"SCALAR"})";
     },
     "exceeds the limit"},
    {"image bufferView outside its buffer",
     [](MiniGltf& g) {
         // tinygltf 2.7 itself would hand the decoder a pointer past the buffer's end.
         g.bufferViews += R"(,{"buffer":0,"byteOffset":40,"byteLength":100000})";
         g.extra = R"(,"images":[{"bufferView":2,"mimeType":"image/png"}])";
     },
     "image 0"},
};

TEST(GltfCorruptInput, BrokenHandWrittenGltf)
{
    ScratchDir dir;
    // The unbroken file loads, so each failure below is caused by its one change.
    const GltfModel intact = loadGltfModel(oneTriangle().write(dir, "intact"));
    ASSERT_EQ(intact.triangleCount(), 1u);

    for (const BrokenCase& c : kBrokenCases) {
        SCOPED_TRACE(c.name);
        MiniGltf g = oneTriangle();
        c.breakIt(g);
        const std::string message = expectRejected(g.write(dir, "broken"));
        EXPECT_NE(message.find(c.expectedInMessage), std::string::npos) << message;
    }
}

} // namespace
} // namespace lumar
