// Small glTF files built in a test for the static-model features of issue 20 (samplers,
// vertex colours, the second uv set, occlusion, texture transforms, quantized attributes,
// unlit, alpha modes, instancing): quads in the xy-plane, with their textures as PNG files
// beside the .gltf. Shared by the loader's unit tests and the GL tests that render them.
#pragma once

#include <array>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <string>
#include <vector>

#include <stb_image_write.h>

#include "core/image.h"
#include "mini_gltf.h"
#include "render_test_support.h"

namespace lumar::test {

// `image` (RGBA8) as a PNG file.
inline void writePngFile(const std::filesystem::path& file, const Image8& image)
{
    std::vector<uint8_t> bytes;
    const auto append = [](void* context, void* data, int size) {
        auto* out = static_cast<std::vector<uint8_t>*>(context);
        const auto* p = static_cast<const uint8_t*>(data);
        out->insert(out->end(), p, p + size);
    };
    stbi_write_png_to_func(append, &bytes, image.width, image.height, 4, image.data.data(), image.width * 4);
    writeBytes(file, bytes);
}

// A width x height RGBA image of one colour per texel, from `texels` (row 0 = top = v 0).
inline Image8 texelImage(int width, int height, const std::vector<std::array<uint8_t, 4>>& texels)
{
    Image8 image(width, height, 4);
    for (int y = 0; y < height; ++y) {
        for (int x = 0; x < width; ++x) {
            std::memcpy(image.at(x, y), texels[size_t(y * width + x)].data(), 4);
        }
    }
    return image;
}

// Accessors appended one by one (each in its own bufferView), primitives, materials,
// textures, samplers and images as JSON text.
struct FeatureGltf : MiniGltf {
    int accessorCount = 0;
    std::vector<std::string> primitives; // of mesh 0
    std::vector<std::string> materialList;
    std::vector<std::string> textures;
    std::vector<std::string> samplers;
    std::vector<std::string> images;
    std::vector<std::string> extensionsUsed;
    std::vector<std::string> extensionsRequired;
    std::string node = R"({"mesh":0})";

    template <typename T>
    int accessor(const std::vector<T>& values, int componentType, const char* type, size_t count,
                 bool normalized = false)
    {
        while (bin.size() % 4 != 0) {
            bin.push_back(0);
        }
        const size_t offset = bin.size();
        bin.resize(offset + values.size() * sizeof(T));
        std::memcpy(bin.data() + offset, values.data(), values.size() * sizeof(T));
        const int view = accessorCount;
        if (!bufferViews.empty()) {
            bufferViews += ",";
            accessors += ",";
        }
        bufferViews += R"({"buffer":0,"byteOffset":)" + std::to_string(offset) + R"(,"byteLength":)" +
                       std::to_string(values.size() * sizeof(T)) + "}";
        accessors += R"({"bufferView":)" + std::to_string(view) + R"(,"componentType":)" +
                     std::to_string(componentType) + R"(,"count":)" + std::to_string(count) + R"(,"type":")" + type +
                     "\"" + (normalized ? R"(,"normalized":true)" : "") + "}";
        return accessorCount++;
    }

    // An axis-aligned quad (x0, y0)-(x1, y1) at depth z, facing +z, uv (u0, v0) at its top-left
    // corner (x0, y1) and (u1, v1) at the bottom-right; `attributes` adds more ("COLOR_0":N,...).
    std::string quadAttributes(float x0, float y0, float x1, float y1, float z, float u0, float v0, float u1, float v1)
    {
        const int position = accessor<float>({x0, y1, z, x1, y1, z, x1, y0, z, x0, y0, z}, 5126, "VEC3", 4);
        const int uv = accessor<float>({u0, v0, u1, v0, u1, v1, u0, v1}, 5126, "VEC2", 4);
        return R"("POSITION":)" + std::to_string(position) + R"(,"TEXCOORD_0":)" + std::to_string(uv);
    }
    int quadIndices() { return accessor<uint16_t>({0, 3, 2, 0, 2, 1}, 5123, "SCALAR", 6); }

    void primitive(const std::string& attributes, int material)
    {
        primitives.push_back(R"({"attributes":{)" + attributes + R"(},"indices":)" + std::to_string(quadIndices()) +
                             R"(,"material":)" + std::to_string(material) + "}");
    }
    int material(const std::string& json)
    {
        materialList.push_back(json);
        return int(materialList.size()) - 1;
    }
    // A texture of `image`, written as NAME.png beside the model, with a sampler (JSON, or
    // empty for none).
    int texture(const ScratchDir& dir, const std::string& name, const Image8& image, const std::string& sampler = {})
    {
        writePngFile(dir.file(name + ".png"), image);
        images.push_back(R"({"uri":")" + name + R"(.png"})");
        std::string json = R"({"source":)" + std::to_string(images.size() - 1);
        if (!sampler.empty()) {
            samplers.push_back(sampler);
            json += R"(,"sampler":)" + std::to_string(samplers.size() - 1);
        }
        textures.push_back(json + "}");
        return int(textures.size()) - 1;
    }

    [[nodiscard]] std::filesystem::path save(const ScratchDir& dir, const std::string& name)
    {
        const auto join = [](const std::vector<std::string>& parts) {
            std::string out;
            for (const std::string& part : parts) {
                out += (out.empty() ? "" : ",") + part;
            }
            return out;
        };
        meshes = R"({"primitives":[)" + join(primitives) + "]}";
        nodes = node;
        materials = join(materialList);
        extra.clear();
        if (!textures.empty()) {
            extra += R"(,"textures":[)" + join(textures) + "]";
        }
        if (!samplers.empty()) {
            extra += R"(,"samplers":[)" + join(samplers) + "]";
        }
        if (!images.empty()) {
            extra += R"(,"images":[)" + join(images) + "]";
        }
        if (!extensionsUsed.empty()) {
            std::vector<std::string> quoted;
            for (const std::string& e : extensionsUsed) {
                quoted.push_back("\"" + e + "\"");
            }
            extra += R"(,"extensionsUsed":[)" + join(quoted) + "]";
        }
        if (!extensionsRequired.empty()) {
            std::vector<std::string> quoted;
            for (const std::string& e : extensionsRequired) {
                quoted.push_back("\"" + e + "\"");
            }
            extra += R"(,"extensionsRequired":[)" + join(quoted) + "]";
        }
        return write(dir, name);
    }
};

} // namespace lumar::test
