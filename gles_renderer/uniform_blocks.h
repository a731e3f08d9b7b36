// C++ mirrors of the std140 uniform blocks in shaders_es/mesh.vert and mesh.frag. Every
// member is a vec4 or a matrix of vec4 columns, so std140 adds no hidden padding; the
// static_asserts pin the offsets the shaders rely on.
#pragma once

#include <cstddef>

#include <glm/glm.hpp>

namespace lumar {

// Binding points shared by the C++ side and every program.
inline constexpr unsigned kFrameBlockBinding = 0;
inline constexpr unsigned kMaterialBlockBinding = 1;

// Per frame: "uniform Frame" in mesh.vert / mesh.frag.
struct FrameUniforms {
    glm::mat4 clipFromCamera{1.0f};
    // mat3 in std140: three columns, each padded to a vec4.
    glm::vec4 environmentFromCamera[3] = {{1, 0, 0, 0}, {0, 1, 0, 0}, {0, 0, 1, 0}};
    // SH9 of the environment's radiance, each already multiplied by the clamped-cosine band
    // factor / pi and the intensity, so the shader's sum is diffuse irradiance / pi (rgb).
    glm::vec4 irradianceSH[9] = {};
    // x: the specular map's largest mip level (roughness 1 samples it); yzw unused.
    glm::vec4 environmentParams{0.0f};
};
static_assert(offsetof(FrameUniforms, clipFromCamera) == 0);
static_assert(offsetof(FrameUniforms, environmentFromCamera) == 64);
static_assert(offsetof(FrameUniforms, irradianceSH) == 112);
static_assert(offsetof(FrameUniforms, environmentParams) == 256);
static_assert(sizeof(FrameUniforms) == 272);

// Per material: "uniform Material" in mesh.frag.
struct MaterialUniforms {
    glm::vec4 baseColorFactor{1.0f};
    // xyz: emissive factor; w: normal-map scale (0 when there is no normal map, which
    // leaves the flat default texture's normal exactly unchanged).
    glm::vec4 emissiveNormalScale{0.0f};
    // x: metallic factor, y: roughness factor.
    glm::vec4 metallicRoughness{1.0f, 1.0f, 0.0f, 0.0f};
};
static_assert(offsetof(MaterialUniforms, baseColorFactor) == 0);
static_assert(offsetof(MaterialUniforms, emissiveNormalScale) == 16);
static_assert(offsetof(MaterialUniforms, metallicRoughness) == 32);
static_assert(sizeof(MaterialUniforms) == 48);

} // namespace lumar
