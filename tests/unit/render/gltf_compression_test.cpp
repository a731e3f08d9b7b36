// Compressed glTF geometry (issue 20): EXT_meshopt_compression files written here with
// meshoptimizer's encoder (no Khronos sample uses it) load exactly as their uncompressed
// twins; the Khronos Box in its Draco variant loads as the plain Box within Draco's
// quantisation; truncated or corrupt compressed data ends in one line naming the file and
// the buffer view or primitive, never a crash.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <string>
#include <utility>
#include <vector>

#include <glm/glm.hpp>
#include <gtest/gtest.h>
#include <meshoptimizer.h>
#include <tiny_gltf.h>

#include "gles_renderer/assets/gltf_compression.h"
#include "gles_renderer/assets/gltf_meshopt.h"
#include "gles_renderer/assets/gltf_model.h"
#include "render_test_support.h"

namespace lumar {
namespace {

using test::ScratchDir;

std::string readText(const std::filesystem::path& file)
{
    const std::vector<uint8_t> bytes = test::readBytes(file);
    return {bytes.begin(), bytes.end()};
}

std::string expectRejected(const std::filesystem::path& file)
{
    return test::expectInputErrorNamingFile([&] { (void)loadGltfModel(file); }, file);
}

template <typename T> std::vector<uint8_t> bytesOf(const std::vector<T>& values)
{
    std::vector<uint8_t> bytes(values.size() * sizeof(T));
    std::memcpy(bytes.data(), values.data(), bytes.size());
    return bytes;
}

// A unit cube: 6 faces of 4 vertices (positions, normals), 36 u16 indices.
struct Cube {
    std::vector<float> positions, normals;
    std::vector<uint16_t> indices;
};

Cube unitCube()
{
    Cube cube;
    for (int axis = 0; axis < 3; ++axis) {
        for (const float sign : {-1.0f, 1.0f}) {
            const auto base = uint16_t(cube.positions.size() / 3);
            const int u = (axis + 1) % 3, v = (axis + 2) % 3;
            for (int corner = 0; corner < 4; ++corner) {
                float p[3], n[3] = {0, 0, 0};
                p[axis] = 0.5f * sign;
                p[u] = (corner & 1) ? 0.5f : -0.5f;
                p[v] = (corner & 2) ? 0.5f : -0.5f;
                n[axis] = sign;
                cube.positions.insert(cube.positions.end(), p, p + 3);
                cube.normals.insert(cube.normals.end(), n, n + 3);
            }
            // Counter-clockwise seen from outside: (u, v) is right-handed with +axis.
            const bool flip = sign < 0;
            const uint16_t a = base, b = uint16_t(base + 1), c = uint16_t(base + 3), d = uint16_t(base + 2);
            if (!flip) {
                cube.indices.insert(cube.indices.end(), {a, b, c, a, c, d});
            } else {
                cube.indices.insert(cube.indices.end(), {a, c, b, a, d, c});
            }
        }
    }
    return cube;
}

// One buffer view's data, and how EXT_meshopt_compression stores it.
struct Stream {
    std::vector<uint8_t> raw;
    size_t stride = 0;
    size_t count = 0;
    std::string mode = "ATTRIBUTES";
    std::string filter = "NONE";
    std::vector<uint8_t> encoded; // empty: stored uncompressed
};

Stream attributes(std::vector<uint8_t> raw, size_t stride)
{
    Stream s;
    s.count = raw.size() / stride;
    s.raw = std::move(raw);
    s.stride = stride;
    return s;
}

void encode(Stream& s)
{
    if (s.mode == "ATTRIBUTES") {
        s.encoded.resize(meshopt_encodeVertexBufferBound(s.count, s.stride));
        s.encoded.resize(
            meshopt_encodeVertexBuffer(s.encoded.data(), s.encoded.size(), s.raw.data(), s.count, s.stride));
        return;
    }
    std::vector<uint32_t> indices(s.count);
    for (size_t i = 0; i < s.count; ++i) {
        indices[i] = s.stride == 2 ? uint32_t(s.raw[2 * i] | s.raw[2 * i + 1] << 8) : 0;
        if (s.stride == 4) {
            std::memcpy(&indices[i], s.raw.data() + 4 * i, 4);
        }
    }
    if (s.mode == "TRIANGLES") {
        s.encoded.resize(meshopt_encodeIndexBufferBound(s.count, 65536));
        s.encoded.resize(meshopt_encodeIndexBuffer(s.encoded.data(), s.encoded.size(), indices.data(), s.count));
    } else {
        s.encoded.resize(meshopt_encodeIndexSequenceBound(s.count, 65536));
        s.encoded.resize(meshopt_encodeIndexSequence(s.encoded.data(), s.encoded.size(), indices.data(), s.count));
    }
}

void append(std::vector<uint8_t>& bin, const std::vector<uint8_t>& bytes, size_t& offset)
{
    bin.resize((bin.size() + 3) / 4 * 4, 0);
    offset = bin.size();
    bin.insert(bin.end(), bytes.begin(), bytes.end());
}

// A model of the streams (view i = stream i): compressed ones in buffer 0 with their raw
// layout in fallback buffer 1 (no uri); `accessors` and `meshes` are JSON array contents.
struct MeshoptFile {
    std::vector<Stream> streams;
    std::string accessors;
    std::string meshes;
    std::string fallbackBuffer = R"("extensions":{"EXT_meshopt_compression":{"fallback":true}})";
    bool required = true;

    // Returns the JSON; `bin` receives buffer 0's bytes.
    std::string json(std::vector<uint8_t>& bin, bool glb) const
    {
        std::string views;
        size_t fallbackBytes = 0;
        for (const Stream& s : streams) {
            size_t offset = 0;
            std::string view;
            if (s.encoded.empty()) {
                append(bin, s.raw, offset);
                view = R"({"buffer":0,"byteOffset":)" + std::to_string(offset) + R"(,"byteLength":)" +
                       std::to_string(s.raw.size());
            } else {
                append(bin, s.encoded, offset);
                fallbackBytes = (fallbackBytes + 3) / 4 * 4;
                view = R"({"buffer":1,"byteOffset":)" + std::to_string(fallbackBytes) + R"(,"byteLength":)" +
                       std::to_string(s.raw.size());
                fallbackBytes += s.raw.size();
            }
            if (s.mode == "ATTRIBUTES") {
                view += R"(,"byteStride":)" + std::to_string(s.stride);
            }
            if (!s.encoded.empty()) {
                view += R"(,"extensions":{"EXT_meshopt_compression":{"buffer":0,"byteOffset":)" +
                        std::to_string(offset) + R"(,"byteLength":)" + std::to_string(s.encoded.size()) +
                        R"(,"byteStride":)" + std::to_string(s.stride) + R"(,"count":)" + std::to_string(s.count) +
                        R"(,"mode":")" + s.mode + R"(","filter":")" + s.filter + R"("}})";
            }
            views += (views.empty() ? "" : ",") + view + "}";
        }
        std::string buffer0 = R"({"byteLength":)" + std::to_string(bin.size()) + (glb ? "}" : R"(,"uri":"data.bin"})");
        std::string json = R"({"asset":{"version":"2.0"},"scene":0,"scenes":[{"nodes":[0]}],"nodes":[{"mesh":0}],)";
        json += R"("extensionsUsed":["EXT_meshopt_compression"],)";
        if (required) {
            json += R"("extensionsRequired":["EXT_meshopt_compression"],)";
        }
        json += R"("buffers":[)" + buffer0 + R"(,{"byteLength":)" + std::to_string(std::max<size_t>(fallbackBytes, 1)) +
                (fallbackBuffer.empty() ? "" : "," + fallbackBuffer) + "}],";
        json += R"("bufferViews":[)" + views + "],";
        json += R"("accessors":[)" + accessors + "],";
        json += R"("meshes":[)" + meshes + "]}";
        return json;
    }

    std::filesystem::path writeGltf(const ScratchDir& dir, const std::string& name) const
    {
        std::vector<uint8_t> bin;
        const std::string text = json(bin, false);
        test::writeBytes(dir.file("data.bin"), bin);
        test::writeText(dir.file(name), text);
        return dir.file(name);
    }

    std::filesystem::path writeGlb(const ScratchDir& dir, const std::string& name) const
    {
        std::vector<uint8_t> bin;
        std::string text = json(bin, true);
        text.resize((text.size() + 3) / 4 * 4, ' ');
        bin.resize((bin.size() + 3) / 4 * 4, 0);
        std::vector<uint8_t> glb;
        const auto put32 = [&](uint32_t v) {
            for (int shift = 0; shift < 32; shift += 8) {
                glb.push_back(uint8_t(v >> shift));
            }
        };
        put32(0x46546C67);
        put32(2);
        put32(uint32_t(12 + 8 + text.size() + 8 + bin.size()));
        put32(uint32_t(text.size()));
        put32(0x4E4F534A);
        glb.insert(glb.end(), text.begin(), text.end());
        put32(uint32_t(bin.size()));
        put32(0x004E4942);
        glb.insert(glb.end(), bin.begin(), bin.end());
        test::writeBytes(dir.file(name), glb);
        return dir.file(name);
    }
};

constexpr const char* kCubeAccessors =
    R"({"bufferView":0,"componentType":5126,"count":24,"type":"VEC3","min":[-0.5,-0.5,-0.5],"max":[0.5,0.5,0.5]},)"
    R"({"bufferView":1,"componentType":5126,"count":24,"type":"VEC3"},)"
    R"({"bufferView":2,"componentType":5123,"count":36,"type":"SCALAR"})";
constexpr const char* kCubeMesh = R"({"primitives":[{"attributes":{"POSITION":0,"NORMAL":1},"indices":2}]})";

// The cube as a meshopt file: positions and normals (attributes, normals with the
// exponential filter) and indices (triangles), each stream compressed when `compress`.
MeshoptFile meshoptCube(bool compress)
{
    const Cube cube = unitCube();
    MeshoptFile file;
    file.streams.push_back(attributes(bytesOf(cube.positions), 12));
    Stream normals = attributes(bytesOf(cube.normals), 12);
    if (compress) {
        // Exponential filter with 24-bit mantissas: every value here (0, +-1) stays exact.
        std::vector<uint8_t> filtered(normals.raw.size());
        meshopt_encodeFilterExp(filtered.data(), normals.count * 3, 4, 24, cube.normals.data());
        normals.raw = filtered;
        normals.filter = "EXPONENTIAL";
    }
    file.streams.push_back(normals);
    Stream indices;
    indices.raw = bytesOf(cube.indices);
    indices.count = cube.indices.size();
    indices.stride = 2;
    indices.mode = "TRIANGLES";
    file.streams.push_back(indices);
    if (compress) {
        for (Stream& s : file.streams) {
            encode(s);
        }
    }
    file.accessors = kCubeAccessors;
    file.meshes = kCubeMesh;
    return file;
}

void expectSameGeometry(const GltfModel& got, const GltfModel& expected)
{
    ASSERT_EQ(got.primitives.size(), expected.primitives.size());
    for (size_t p = 0; p < got.primitives.size(); ++p) {
        const GltfPrimitive& a = got.primitives[p];
        const GltfPrimitive& b = expected.primitives[p];
        // The triangle codec keeps the order of triangles but may rotate each one's corners.
        ASSERT_EQ(a.indices.size(), b.indices.size());
        for (size_t t = 0; t + 2 < a.indices.size(); t += 3) {
            bool rotated = false;
            for (size_t shift = 0; shift < 3; ++shift) {
                rotated = rotated ||
                          (a.indices[t] == b.indices[t + shift] && a.indices[t + 1] == b.indices[t + (shift + 1) % 3] &&
                           a.indices[t + 2] == b.indices[t + (shift + 2) % 3]);
            }
            EXPECT_TRUE(rotated) << "triangle " << t / 3;
        }
        ASSERT_EQ(a.positions.size(), b.positions.size());
        for (size_t i = 0; i < a.positions.size(); ++i) {
            EXPECT_EQ(a.positions[i], b.positions[i]) << "vertex " << i;
            EXPECT_LT(glm::length(a.normals[i] - b.normals[i]), 1e-6f) << "vertex " << i;
        }
    }
}

TEST(GltfMeshopt, CompressedCubeLoadsAsItsUncompressedTwin)
{
    if (!gltf::meshoptDecoderBuilt()) {
        GTEST_SKIP() << "built without the meshopt decoder (LUMAR_WITH_MESHOPT_DECODER)";
    }
    ScratchDir dir;
    const MeshoptFile plainFile = meshoptCube(false);
    const GltfModel plain = loadGltfModel(plainFile.writeGltf(dir, "plain.gltf"));
    ASSERT_EQ(plain.triangleCount(), 12u);

    const MeshoptFile compressed = meshoptCube(true);
    for (const Stream& s : compressed.streams) {
        ASSERT_FALSE(s.encoded.empty());
        EXPECT_LT(s.encoded.size(), s.raw.size() + 64);
    }
    expectSameGeometry(loadGltfModel(compressed.writeGltf(dir, "meshopt.gltf")), plain);
    // The GLB form: the fallback buffer is buffer 1 without a uri beside the binary chunk.
    expectSameGeometry(loadGltfModel(compressed.writeGlb(dir, "meshopt.glb")), plain);
    // A placeholder without the fallback mark is a fallback buffer too.
    MeshoptFile unmarked = compressed;
    unmarked.fallbackBuffer.clear();
    expectSameGeometry(loadGltfModel(unmarked.writeGlb(dir, "unmarked.glb")), plain);
    // Used but not required: the compressed data is still what is read.
    MeshoptFile optional = compressed;
    optional.required = false;
    expectSameGeometry(loadGltfModel(optional.writeGltf(dir, "optional.gltf")), plain);
}

TEST(GltfMeshopt, IndexSequenceOfAStrip)
{
    if (!gltf::meshoptDecoderBuilt()) {
        GTEST_SKIP() << "built without the meshopt decoder (LUMAR_WITH_MESHOPT_DECODER)";
    }
    ScratchDir dir;
    // Four vertices as a strip (mode 5), indices stored with the INDICES codec as u32.
    MeshoptFile file;
    file.streams.push_back(attributes(bytesOf(std::vector<float>{0, 0, 0, 0, 1, 0, 1, 0, 0, 1, 1, 0}), 12));
    Stream indices;
    indices.raw = bytesOf(std::vector<uint32_t>{0, 1, 2, 3});
    indices.count = 4;
    indices.stride = 4;
    indices.mode = "INDICES";
    file.streams.push_back(indices);
    for (Stream& s : file.streams) {
        encode(s);
    }
    file.accessors = R"({"bufferView":0,"componentType":5126,"count":4,"type":"VEC3"},)"
                     R"({"bufferView":1,"componentType":5125,"count":4,"type":"SCALAR"})";
    file.meshes = R"({"primitives":[{"attributes":{"POSITION":0},"indices":1,"mode":5}]})";
    const GltfModel model = loadGltfModel(file.writeGltf(dir, "strip.gltf"));
    ASSERT_EQ(model.primitives.size(), 1u);
    EXPECT_EQ(model.primitives[0].indices, (std::vector<uint32_t>{0, 1, 2, 1, 3, 2}));
    EXPECT_EQ(model.primitives[0].positions[3], glm::vec3(1, 1, 0));
}

// The octahedral and quaternion filters produce integer data (read by KHR_mesh_quantization
// accessors), checked here on the decoded buffer view itself.
TEST(GltfMeshopt, OctahedralAndQuaternionFiltersDecodeToTheEncodedValues)
{
    if (!gltf::meshoptDecoderBuilt()) {
        GTEST_SKIP() << "built without the meshopt decoder (LUMAR_WITH_MESHOPT_DECODER)";
    }
    const std::vector<glm::vec3> directions = {glm::normalize(glm::vec3(1, 2, 3)), glm::vec3(0, 0, -1),
                                               glm::normalize(glm::vec3(-1, 0.5f, 0.25f)), glm::vec3(1, 0, 0)};
    std::vector<float> octInput;
    for (const glm::vec3& d : directions) {
        octInput.insert(octInput.end(), {d.x, d.y, d.z, 1.0f});
    }
    const std::vector<glm::vec4> rotations = {glm::vec4(0, 0, 0, 1), glm::normalize(glm::vec4(1, 2, 3, 4)),
                                              glm::normalize(glm::vec4(-0.3f, 0.1f, 0.9f, -0.2f)),
                                              glm::vec4(0, 1, 0, 0)};
    std::vector<float> quatInput;
    for (const glm::vec4& q : rotations) {
        quatInput.insert(quatInput.end(), {q.x, q.y, q.z, q.w});
    }

    tinygltf::Model model;
    const auto addView = [&](const std::vector<uint8_t>& filtered, size_t stride, const char* filter) {
        std::vector<uint8_t> encoded(meshopt_encodeVertexBufferBound(filtered.size() / stride, stride));
        encoded.resize(meshopt_encodeVertexBuffer(encoded.data(), encoded.size(), filtered.data(),
                                                  filtered.size() / stride, stride));
        tinygltf::Buffer buffer;
        buffer.data = encoded;
        model.buffers.push_back(buffer);
        tinygltf::Value::Object extension;
        extension["buffer"] = tinygltf::Value(int(model.buffers.size() - 1));
        extension["byteLength"] = tinygltf::Value(int(encoded.size()));
        extension["byteStride"] = tinygltf::Value(int(stride));
        extension["count"] = tinygltf::Value(int(filtered.size() / stride));
        extension["mode"] = tinygltf::Value(std::string("ATTRIBUTES"));
        extension["filter"] = tinygltf::Value(std::string(filter));
        tinygltf::BufferView view;
        view.buffer = 0;
        view.byteLength = filtered.size();
        view.byteStride = stride;
        view.extensions["EXT_meshopt_compression"] = tinygltf::Value(extension);
        model.bufferViews.push_back(view);
    };
    std::vector<uint8_t> oct(directions.size() * 8);
    meshopt_encodeFilterOct(oct.data(), directions.size(), 8, 16, octInput.data());
    addView(oct, 8, "OCTAHEDRAL");
    std::vector<uint8_t> quat(rotations.size() * 8);
    meshopt_encodeFilterQuat(quat.data(), rotations.size(), 8, 16, quatInput.data());
    addView(quat, 8, "QUATERNION");

    size_t budget = gltf::kMaxDecodedBytes;
    gltf::decodeMeshoptBufferViews(model, budget);
    EXPECT_EQ(budget, gltf::kMaxDecodedBytes - 64);
    for (int v = 0; v < 2; ++v) {
        const tinygltf::BufferView& view = model.bufferViews[size_t(v)];
        EXPECT_TRUE(view.extensions.empty());
        ASSERT_EQ(view.byteLength, 32u);
        const auto& data = model.buffers[size_t(view.buffer)].data;
        ASSERT_EQ(data.size(), 32u);
        for (size_t i = 0; i < 4; ++i) {
            int16_t s[4];
            std::memcpy(s, data.data() + 8 * i, 8);
            const glm::vec4 decoded(s[0] / 32767.0f, s[1] / 32767.0f, s[2] / 32767.0f, s[3] / 32767.0f);
            if (v == 0) { // normalised signed shorts, xyz a unit vector
                EXPECT_LT(glm::length(glm::vec3(decoded) - directions[i]), 1e-3f) << i;
            } else { // q and -q are one rotation
                const float dot = std::abs(glm::dot(decoded, rotations[i]));
                EXPECT_GT(dot, 1.0f - 1e-3f) << i;
            }
        }
    }
}

TEST(GltfMeshopt, TruncatedOrCorruptDataIsOneLineNamingTheBufferView)
{
    if (!gltf::meshoptDecoderBuilt()) {
        GTEST_SKIP() << "built without the meshopt decoder (LUMAR_WITH_MESHOPT_DECODER)";
    }
    ScratchDir dir;
    const MeshoptFile good = meshoptCube(true);

    // The compressed positions cut short: the decoder runs out of data.
    MeshoptFile truncated = good;
    truncated.streams[0].encoded.resize(truncated.streams[0].encoded.size() / 2);
    std::string message = expectRejected(truncated.writeGltf(dir, "truncated.gltf"));
    EXPECT_NE(message.find("bufferView 0 (EXT_meshopt_compression)"), std::string::npos) << message;
    EXPECT_NE(message.find("truncated or corrupt"), std::string::npos) << message;

    // A wrong header byte.
    MeshoptFile header = good;
    header.streams[2].encoded[0] ^= 0x55;
    message = expectRejected(header.writeGltf(dir, "header.gltf"));
    EXPECT_NE(message.find("bufferView 2"), std::string::npos) << message;

    // Every byte of every stream flipped in turn, and every length: loads or one clean line.
    for (size_t s = 0; s < good.streams.size(); ++s) {
        for (size_t i = 0; i < good.streams[s].encoded.size(); i += 3) {
            MeshoptFile flipped = good;
            flipped.streams[s].encoded[i] ^= 0xA5;
            const auto file = flipped.writeGltf(dir, "flipped.gltf");
            try {
                (void)loadGltfModel(file);
            } catch (const InputError&) {
                expectRejected(file);
            }
            MeshoptFile shortened = good; // (0 bytes would be written as uncompressed data)
            shortened.streams[s].encoded.resize(i + 1);
            expectRejected(shortened.writeGltf(dir, "short.gltf"));
        }
    }
}

TEST(GltfMeshopt, ExtensionObjectsBreakingTheRulesAreRefused)
{
    if (!gltf::meshoptDecoderBuilt()) {
        GTEST_SKIP() << "built without the meshopt decoder (LUMAR_WITH_MESHOPT_DECODER)";
    }
    ScratchDir dir;
    using Edits = std::vector<std::pair<std::string, std::string>>;
    const auto rejectedWith = [&](const Edits& edits, const std::string& expected) {
        const MeshoptFile good = meshoptCube(true);
        std::vector<uint8_t> bin;
        std::string json = good.json(bin, false);
        for (const auto& [from, to] : edits) {
            const size_t at = json.find(from);
            ASSERT_NE(at, std::string::npos) << from;
            json.replace(at, from.size(), to);
        }
        test::writeBytes(dir.file("data.bin"), bin);
        test::writeText(dir.file("bad.gltf"), json);
        const std::string message = expectRejected(dir.file("bad.gltf"));
        EXPECT_NE(message.find(expected), std::string::npos) << message;
    };
    rejectedWith({{R"("mode":"TRIANGLES")", R"("mode":"STRIPS")"}}, "mode 'STRIPS' is not");
    rejectedWith({{R"("filter":"EXPONENTIAL")", R"("filter":"QUATERNION")"}}, "does not suit filter QUATERNION");
    rejectedWith({{R"("filter":"EXPONENTIAL")", R"("filter":"ZIP")"}}, "filter 'ZIP' is not");
    rejectedWith({{R"("count":36)", R"("count":35)"}}, "not a multiple of 3");
    rejectedWith(
        {{R"("count":24,"mode":"ATTRIBUTES","filter":"NONE")", R"("count":23,"mode":"ATTRIBUTES","filter":"NONE")"}},
        "is not the bufferView's byteLength");
    rejectedWith({{R"("buffer":0,"byteOffset":0,)", R"("buffer":7,"byteOffset":0,)"}}, "buffer 7 does not exist");
    rejectedWith({{R"("buffer":0,"byteOffset":0,)", R"("buffer":0,"byteOffset":100000,)"}}, "lies outside buffer 0");
    rejectedWith({{R"("mode":"ATTRIBUTES","filter":"NONE")", R"("filter":"NONE")"}}, "mode is missing");
    // A count far beyond what the compressed bytes can hold is refused before allocating.
    rejectedWith({{R"("byteLength":288,"byteStride":12,"extensions")",
                   R"("byteLength":1200000000,"byteStride":12,"extensions")"},
                  {R"("count":24,"mode":"ATTRIBUTES","filter":"NONE")",
                   R"("count":100000000,"mode":"ATTRIBUTES","filter":"NONE")"}},
                 "cannot hold");
}

TEST(GltfCompression, MissingDecoderNamesTheExtension)
{
    if (gltf::dracoDecoderBuilt() && gltf::meshoptDecoderBuilt()) {
        GTEST_SKIP() << "this build has both decoders";
    }
    ScratchDir dir;
    if (!gltf::meshoptDecoderBuilt()) {
        const std::string message = expectRejected(meshoptCube(true).writeGltf(dir, "meshopt.gltf"));
        EXPECT_NE(message.find("EXT_meshopt_compression"), std::string::npos) << message;
    }
    if (!gltf::dracoDecoderBuilt()) {
        const auto file = test::testDataPath("khronos/Box/Draco/Box.gltf");
        const std::string message = expectRejected(file);
        EXPECT_NE(message.find("KHR_draco_mesh_compression"), std::string::npos) << message;
    }
}

// Draco: the decoded Box against the plain one. Draco re-orders vertices and triangles, so
// triangles are matched by their corner positions (quantised to 1/2^14 of the box here).
struct Corner {
    glm::vec3 position, normal;
};
using Triangle = std::array<Corner, 3>;

std::vector<Triangle> trianglesOf(const GltfModel& model)
{
    std::vector<Triangle> triangles;
    for (const GltfPrimitive& p : model.primitives) {
        for (size_t i = 0; i + 2 < p.indices.size(); i += 3) {
            Triangle t;
            for (size_t c = 0; c < 3; ++c) {
                const uint32_t v = p.indices[i + c];
                t[c] = {glm::vec3(p.modelFromMesh * glm::vec4(p.positions[v], 1.0f)), p.normals[v]};
            }
            triangles.push_back(t);
        }
    }
    return triangles;
}

// Whether `a` is `b` up to a rotation of its corners (the winding kept).
bool sameTriangle(const Triangle& a, const Triangle& b, float tolerance)
{
    for (size_t shift = 0; shift < 3; ++shift) {
        bool all = true;
        for (size_t c = 0; c < 3 && all; ++c) {
            const Corner& x = a[c];
            const Corner& y = b[(c + shift) % 3];
            all = glm::length(x.position - y.position) < tolerance && glm::length(x.normal - y.normal) < 1e-2f;
        }
        if (all) {
            return true;
        }
    }
    return false;
}

TEST(GltfDraco, DracoBoxMatchesThePlainBox)
{
    if (!gltf::dracoDecoderBuilt()) {
        GTEST_SKIP() << "built without Draco (LUMAR_WITH_DRACO)";
    }
    const GltfModel plain = loadGltfModel(test::testDataPath("khronos/Box/Box.glb"));
    const GltfModel draco = loadGltfModel(test::testDataPath("khronos/Box/Draco/Box.gltf"));
    ASSERT_EQ(draco.primitives.size(), 1u);
    EXPECT_EQ(draco.primitives[0].positions.size(), 24u);
    EXPECT_EQ(draco.triangleCount(), plain.triangleCount());
    EXPECT_EQ(draco.primitives[0].material, plain.primitives[0].material);
    // The attribute ids map NORMAL to 0 and POSITION to 1: swapped, the box would be 2 wide.
    EXPECT_LT(glm::length(draco.boundsMax - plain.boundsMax), 1e-3f);
    EXPECT_LT(glm::length(draco.boundsMin - plain.boundsMin), 1e-3f);
    const std::vector<Triangle> expected = trianglesOf(plain);
    std::vector<Triangle> got = trianglesOf(draco);
    ASSERT_EQ(got.size(), expected.size());
    for (const Triangle& t : expected) {
        const auto match =
            std::find_if(got.begin(), got.end(), [&](const Triangle& g) { return sameTriangle(g, t, 1e-3f); });
        ASSERT_NE(match, got.end()) << "a triangle of the plain box is missing";
        got.erase(match);
    }
}

TEST(GltfDraco, TruncatedOrCorruptDracoDataIsOneLineNamingThePrimitive)
{
    if (!gltf::dracoDecoderBuilt()) {
        GTEST_SKIP() << "built without Draco (LUMAR_WITH_DRACO)";
    }
    ScratchDir dir;
    const std::string json = readText(test::testDataPath("khronos/Box/Draco/Box.gltf"));
    const std::vector<uint8_t> bin = test::readBytes(test::testDataPath("khronos/Box/Draco/Box.bin"));
    ASSERT_EQ(bin.size(), 120u);
    test::writeText(dir.file("Box.gltf"), json);

    // Cut short: the buffer view (118 bytes) still claims the whole stream.
    std::vector<uint8_t> shortened(bin.begin(), bin.begin() + 60);
    std::string bad = json;
    bad.replace(bad.find(R"("byteLength": 120)"), 17, R"("byteLength": 60)");
    bad.replace(bad.find(R"("byteLength": 118)"), 17, R"("byteLength": 58)");
    test::writeBytes(dir.file("Box.bin"), shortened);
    test::writeText(dir.file("short.gltf"), bad);
    std::string message = expectRejected(dir.file("short.gltf"));
    EXPECT_NE(message.find("mesh 0 primitive 0 (KHR_draco_mesh_compression)"), std::string::npos) << message;
    EXPECT_NE(message.find("bufferView 0"), std::string::npos) << message;

    // Every length and flipped bytes: loads or one clean line.
    for (size_t length = 0; length < 118; length += 5) {
        std::string cut = json;
        cut.replace(cut.find(R"("byteLength": 118)"), 17, R"("byteLength": )" + std::to_string(length));
        test::writeBytes(dir.file("Box.bin"), bin);
        test::writeText(dir.file("cut.gltf"), cut);
        expectRejected(dir.file("cut.gltf"));
    }
    test::writeText(dir.file("Box.gltf"), json);
    for (size_t i = 0; i < 118; ++i) {
        for (const uint8_t mask : {uint8_t(0x01), uint8_t(0x80), uint8_t(0xFF)}) {
            std::vector<uint8_t> flipped = bin;
            flipped[i] ^= mask;
            test::writeBytes(dir.file("Box.bin"), flipped);
            try {
                (void)loadGltfModel(dir.file("Box.gltf"));
            } catch (const InputError&) {
                expectRejected(dir.file("Box.gltf"));
            }
        }
    }

    // An attribute id the Draco data does not have, and an accessor count that disagrees.
    test::writeBytes(dir.file("Box.bin"), bin);
    bad = json;
    bad.replace(bad.find(R"("POSITION": 1)"), 13, R"("POSITION": 9)");
    test::writeText(dir.file("id.gltf"), bad);
    message = expectRejected(dir.file("id.gltf"));
    EXPECT_NE(message.find("Draco attribute id 9 does not exist"), std::string::npos) << message;
    bad = json;
    bad.replace(bad.find(R"("count": 36)"), 11, R"("count": 30)");
    test::writeText(dir.file("count.gltf"), bad);
    message = expectRejected(dir.file("count.gltf"));
    EXPECT_NE(message.find("index accessor 0 has count 30"), std::string::npos) << message;
}

} // namespace
} // namespace lumar
