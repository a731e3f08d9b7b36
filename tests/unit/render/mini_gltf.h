// Small hand-written .gltf files for loader tests: a JSON document assembled from its parts
// plus an external .bin whose bytes the test lays out explicitly.
#pragma once

#include <cstdint>
#include <cstring>
#include <filesystem>
#include <initializer_list>
#include <string>
#include <vector>

#include "render_test_support.h"

namespace lumar::test {

struct MiniGltf {
    std::vector<uint8_t> bin;

    // Appends `values` (4-byte aligned, as glTF requires for float data); returns the offset.
    template <typename T> size_t add(std::initializer_list<T> values)
    {
        while (bin.size() % 4 != 0) {
            bin.push_back(0);
        }
        const size_t offset = bin.size();
        bin.resize(offset + values.size() * sizeof(T));
        std::memcpy(bin.data() + offset, values.begin(), values.size() * sizeof(T));
        return offset;
    }

    // JSON arrays' contents (without the brackets); `extra` holds more top-level members,
    // each preceded by a comma.
    std::string bufferViews;
    std::string accessors;
    std::string meshes;
    std::string nodes = R"({"mesh":0})";
    std::string materials;
    std::string extra;

    // Writes NAME.bin and NAME.gltf into `dir` and returns the .gltf path.
    [[nodiscard]] std::filesystem::path write(const ScratchDir& dir, const std::string& name) const
    {
        const std::string binName = name + ".bin";
        writeBytes(dir.file(binName), bin);
        std::string json = R"({"asset":{"version":"2.0"},"scene":0,"scenes":[{"nodes":[0]}],)";
        json += R"("buffers":[{"uri":")" + binName + R"(","byteLength":)" + std::to_string(bin.size()) + "}],";
        json += R"("bufferViews":[)" + bufferViews + "],";
        json += R"("accessors":[)" + accessors + "],";
        json += R"("meshes":[)" + meshes + "],";
        json += R"("nodes":[)" + nodes + "]";
        if (!materials.empty()) {
            json += R"(,"materials":[)" + materials + "]";
        }
        json += extra + "}";
        const auto path = dir.file(name + ".gltf");
        writeText(path, json);
        return path;
    }
};

// One triangle in the xy-plane, counter-clockwise seen from +z: positions (0,0,0), (1,0,0),
// (0,1,0) as accessor 0 (bufferView 0), u16 indices 0,1,2 as accessor 1 (bufferView 1).
inline MiniGltf oneTriangle()
{
    MiniGltf g;
    const size_t positions = g.add<float>({0, 0, 0, 1, 0, 0, 0, 1, 0});
    const size_t indices = g.add<uint16_t>({0, 1, 2});
    g.bufferViews = R"({"buffer":0,"byteOffset":)" + std::to_string(positions) + R"(,"byteLength":36},)" +
                    R"({"buffer":0,"byteOffset":)" + std::to_string(indices) + R"(,"byteLength":6})";
    g.accessors = R"({"bufferView":0,"componentType":5126,"count":3,"type":"VEC3"},)"
                  R"({"bufferView":1,"componentType":5123,"count":3,"type":"SCALAR"})";
    g.meshes = R"({"primitives":[{"attributes":{"POSITION":0},"indices":1}]})";
    return g;
}

} // namespace lumar::test
