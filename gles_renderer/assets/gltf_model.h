// A glTF 2.0 model loaded into plain CPU data (tinygltf underneath), ready for upload.
// Node transforms are flattened into each primitive's modelFromMesh matrix; skins and morph
// targets are applied in the rest pose, and a model with animations keeps its rig to pose it.
#pragma once

#include <array>
#include <filesystem>
#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "core/image.h"

namespace lumar {

// A glTF sampler's state, as the GL enum values glTF uses (glTF 2.0 §5.26). minFilter 0: the
// file names none, so lumar's default (trilinear) applies; magFilter 0 likewise (linear).
struct GltfSampler {
    int wrapS = 10497; // GL_REPEAT; GL_CLAMP_TO_EDGE 33071, GL_MIRRORED_REPEAT 33648
    int wrapT = 10497;
    int minFilter = 0; // GL_NEAREST 9728, GL_LINEAR 9729, GL_*_MIPMAP_* 9984..9987
    int magFilter = 0; // GL_NEAREST or GL_LINEAR
    auto operator<=>(const GltfSampler&) const = default;
};

struct GltfTexture {
    Image8 image;      // 4 channels RGBA, row 0 = top of the image (glTF's uv (0,0))
    bool srgb = false; // base colour and emissive are sRGB-encoded, the rest linear
};

// Which uv set a material's texture reads and how the uv is transformed first
// (textureInfo.texCoord, KHR_texture_transform): uv' = offset + R(rotation) * (scale * uv).
struct GltfUvTransform {
    int texCoord = 0; // 0: TEXCOORD_0, 1: TEXCOORD_1
    glm::vec2 offset{0.0f};
    float rotation = 0.0f; // radians, counter-clockwise in uv space as the extension defines
    glm::vec2 scale{1.0f};
    // The two rows of the 2x3 matrix taking (u, v, 1) to the transformed uv.
    [[nodiscard]] std::array<glm::vec3, 2> rows() const;
};

// The texture slots of a material, for GltfMaterial::uvTransforms (and the shader's order).
enum class GltfTextureSlot {
    BaseColor,
    MetallicRoughness,
    Normal,
    Emissive,
    Occlusion,
    Specular,
    Lobe,
    TangentRotation,
    Count
};
inline constexpr size_t kGltfTextureSlots = size_t(GltfTextureSlot::Count);

// glTF 2.0 §3.9.4: OPAQUE ignores alpha; MASK discards below alphaCutoff; BLEND mixes with
// what lies behind (drawn after the opaque primitives, back to front, without depth writes).
enum class GltfAlphaMode { Opaque, Mask, Blend };

// The paper's shading parameters (DESIGN.md §6.4): McAllister's one-lobe Lafortune SBRDF in
// the local frame (T, B, N) plus a tangent rotation and the paper's Fresnel factor. Every
// textured parameter is `factor x texel` as glTF does, so an absent texture (white) leaves
// the factor alone.
struct LafortuneParams {
    glm::vec3 diffuse{0.8f};            // rho_d, linear (x the ρd/base-colour texture, sRGB)
    glm::vec3 specular{0.04f};          // rho_s, linear (x the specular texture, sRGB)
    glm::vec3 lobe{-1.0f, -1.0f, 1.0f}; // C_x, C_y, C_z (x the lobe texture's rgb, linear)
    float exponent = 64.0f;             // n (x the lobe texture's alpha)
    float fresnelPhi = 0.0f;            // phi in [0, 1): 0 switches the Fresnel factor off
    float tangentRotation = 0.0f;       // angle / pi in [0, 1] (x the rotation texture's red)
};

// KHR_materials_transmission (+ KHR_materials_ior, KHR_materials_volume). factor 0: none.
struct GltfTransmission {
    float factor = 0.0f;         // share of the light not reflected that passes through (x texel red)
    int texture = -1;            // index into GltfModel::textures, linear r; -1: none
    GltfUvTransform uvTransform; // of `texture`
    // Index of refraction: >= 1, or 0 (the extension's special value: F0 = 1, no bending).
    // Sets the dielectric F0 = ((ior - 1) / (ior + 1))^2 of a metallic-roughness material.
    float ior = 1.5f;
    // KHR_materials_volume: 0 is thin-walled (the view passes straight through); above 0 the
    // object is solid and bends the view at its surface. Model units.
    float thickness = 0.0f;
    // KHR_materials_volume thicknessTexture: its green x `thickness` (index into
    // GltfModel::textures, linear; -1: none). See volumeThickness.
    int thicknessTexture = -1;
    glm::vec3 attenuationColor{1.0f}; // the colour white light turns after attenuationDistance
    float attenuationDistance = std::numeric_limits<float>::infinity(); // > 0, model units
    // What tints the light through: glTF's base colour factor (x the base-colour texel); a
    // preset's clear glass is white.
    glm::vec3 tint{1.0f};
};

struct GltfMaterial {
    std::string name;
    // True when LUMAR_materials_lafortune or a sidecar gave the full parameter set; false for
    // a plain metallic-roughness material, which the shader converts per texel
    // (lafortune_material.h).
    bool hasLafortune = false;
    LafortuneParams lafortune;
    int specularTexture = -1;        // sRGB rgb: rho_s
    int lobeTexture = -1;            // linear rgba: C_x, C_y, C_z, n multipliers
    int tangentRotationTexture = -1; // linear r: rotation angle / pi
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
    // Per GltfTextureSlot: uv set and KHR_texture_transform.
    std::array<GltfUvTransform, kGltfTextureSlots> uvTransforms{};
    int occlusionTexture = -1;      // linear r: ambient occlusion
    float occlusionStrength = 1.0f; // 1 + strength * (texel - 1) darkens the environment light
    bool unlit = false;             // KHR_materials_unlit: base colour x vertex colour x texel
    GltfAlphaMode alphaMode = GltfAlphaMode::Opaque;
    float alphaCutoff = 0.5f; // MASK only
    // Light through the surface (KHR_materials_transmission, _ior, _volume; the `glass`
    // preset), drawn after the opaque primitives as a refraction lookup in the object's own
    // environment maps plus its Fresnel-weighted reflection (shaders_es/transmission.glsl).
    GltfTransmission transmission;
};

struct GltfPrimitive {
    glm::mat4 modelFromMesh{1.0f};
    std::vector<glm::vec3> positions;
    std::vector<glm::vec3> normals;  // generated (flat/area-weighted) when absent
    std::vector<glm::vec2> uvs;      // zeros when absent
    std::vector<glm::vec4> tangents; // generated from uvs when absent (w = handedness)
    std::vector<glm::vec2> uvs1;     // TEXCOORD_1; empty when absent (read as zeros)
    std::vector<glm::vec4> colors;   // COLOR_0 as linear rgba; empty when absent (white)
    std::vector<uint32_t> indices;   // triangles
    int material = -1;               // -1: default material
    // The glTF node it is an instance of and its index in that node's mesh (-1: not from a
    // file): what the rig (gltf_rig.h) poses it by.
    int node = -1;
    int meshPrimitive = -1;
};

struct GltfRig;

struct GltfModel {
    std::filesystem::path file;
    std::vector<GltfPrimitive> primitives;
    std::vector<GltfMaterial> materials;
    std::vector<GltfTexture> textures;
    // Parallel to textures (kept apart so GltfTexture stays a two-member aggregate); a
    // texture without an entry is sampled with the default sampler.
    std::vector<GltfSampler> textureSamplers;
    glm::vec3 boundsMin{0.0f}, boundsMax{0.0f}; // model space (after node transforms)
    // The node hierarchy, skins, morph targets and animations of a model with animations
    // (gltf_rig.h); null for a still one. `primitives` hold the rest pose.
    std::shared_ptr<const GltfRig> rig;
    [[nodiscard]] size_t triangleCount() const;
};

// The volume's thickness (KHR_materials_volume, model units) where the renderer uses it: the
// thickness factor x the mean green of its thickness texture (the renderer takes the volume's
// thickness as one number: its attenuation over it, and 0 for thin-walled). The factor alone
// without a texture, or where `textures` does not hold it.
float volumeThickness(const GltfTransmission& transmission, const std::vector<GltfTexture>& textures);

// Throws InputError "FILE: what is wrong" for a missing, corrupt or unsupported file.
GltfModel loadGltfModel(const std::filesystem::path& file);

} // namespace lumar
