// A glTF 2.0 model loaded into plain CPU data (tinygltf underneath), ready for upload.
// Node transforms are flattened into each primitive's modelFromMesh matrix.
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "core/image.h"

namespace lumar {

struct GltfTexture {
    Image8 image;      // 4 channels RGBA, row 0 = top of the image (glTF's uv (0,0))
    bool srgb = false; // base colour and emissive are sRGB-encoded, the rest linear
};

struct GltfMaterial {
    std::string name;
    glm::vec4 baseColorFactor{1.0f};
    float metallicFactor = 1.0f;
    float roughnessFactor = 1.0f;
    glm::vec3 emissiveFactor{0.0f};
    float normalScale = 1.0f;
    // Indices into GltfModel::textures, -1 when absent.
    int baseColorTexture = -1;
    int metallicRoughnessTexture = -1;
    int normalTexture = -1;
    int emissiveTexture = -1;
    bool doubleSided = false;
};

struct GltfPrimitive {
    glm::mat4 modelFromMesh{1.0f};
    std::vector<glm::vec3> positions;
    std::vector<glm::vec3> normals;  // generated (flat/area-weighted) when absent
    std::vector<glm::vec2> uvs;      // zeros when absent
    std::vector<glm::vec4> tangents; // generated from uvs when absent (w = handedness)
    std::vector<uint32_t> indices;   // triangles
    int material = -1;               // -1: default material
};

struct GltfModel {
    std::filesystem::path file;
    std::vector<GltfPrimitive> primitives;
    std::vector<GltfMaterial> materials;
    std::vector<GltfTexture> textures;
    glm::vec3 boundsMin{0.0f}, boundsMax{0.0f}; // model space (after node transforms)
    [[nodiscard]] size_t triangleCount() const;
};

// Throws InputError "FILE: what is wrong" for a missing, corrupt or unsupported file.
GltfModel loadGltfModel(const std::filesystem::path& file);

} // namespace lumar
