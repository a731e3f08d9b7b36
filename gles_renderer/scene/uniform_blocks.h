// C++ mirrors of the std140 uniform blocks in shaders_es/mesh.vert, mesh.frag and
// material_block.glsl (the Material block every program that reads it includes). Every
// member is a vec4 or a matrix of vec4 columns, so std140 adds no hidden padding; the
// static_asserts pin the offsets the shaders rely on.
#pragma once

#include <cstddef>

#include <glm/glm.hpp>

namespace lumar {

// Binding points shared by the C++ side and every program.
inline constexpr unsigned kFrameBlockBinding = 0;
inline constexpr unsigned kMaterialBlockBinding = 1;

// Per view: "uniform Frame" in mesh.vert / mesh.frag. A view is the frame's camera or one
// cube-face camera of an object's environment map.
struct FrameUniforms {
    glm::mat4 clipFromCamera{1.0f};
    // mat3 in std140: three columns, each padded to a vec4.
    glm::vec4 environmentFromCamera[3] = {{1, 0, 0, 0}, {0, 1, 0, 0}, {0, 0, 1, 0}};
    // x: +1, or -1 when the camera frame is mirrored (cube faces); y: 1 = write linear
    // radiance (environment maps), 0 = tone-mapped sRGB (the frame); z: 1 = the maps are
    // RGBA8 RGBM (decode them, and encode linear output); w: exposure, the factor on
    // radiance before tone mapping (the frame; 1 in environment maps).
    glm::vec4 frameParams{1.0f, 0.0f, 0.0f, 1.0f};
    // The dominant light in this view (DESIGN.md §6.5), written by ShadowPass::fillView; all
    // zero: no light, no shadows (the shading of a renderer without them).
    // Shadow-map clip space (orthographic, [-1, 1]^3) from this view's camera frame.
    glm::mat4 lightClipFromCamera{0.0f};
    // xyz: unit direction towards the light, this view's camera frame; w: 1 = the shadow map
    // holds this frame's casters (sample it), 0 = nothing to sample, everything is lit.
    glm::vec4 lightDirection{0.0f};
    // rgb: the light's irradiance at normal incidence (colour * intensity); w: 1 = a light is set.
    glm::vec4 lightIrradiance{0.0f};
    // x: PCF kernel radius (texels), y: 1 / map size, z: the normal offset (metres: shadow.glsl's
    // lookups move a point this far along its normal), w: depth bias (shadow-map depth units).
    glm::vec4 shadowParams{0.0f};
    // x: the lens effects' bright threshold: mesh.frag's second output is the radiance x
    // exposure above it (lens_effects.h). Only mesh.vert / mesh.frag declare it.
    glm::vec4 lensParams{0.0f};
};
static_assert(offsetof(FrameUniforms, clipFromCamera) == 0);
static_assert(offsetof(FrameUniforms, environmentFromCamera) == 64);
static_assert(offsetof(FrameUniforms, frameParams) == 112);
static_assert(offsetof(FrameUniforms, lightClipFromCamera) == 128);
static_assert(offsetof(FrameUniforms, lightDirection) == 192);
static_assert(offsetof(FrameUniforms, lightIrradiance) == 208);
static_assert(offsetof(FrameUniforms, shadowParams) == 224);
static_assert(offsetof(FrameUniforms, lensParams) == 240);
static_assert(sizeof(FrameUniforms) == 256);

// Per material: "uniform Material", declared once in shaders_es/material_block.glsl and
// included by mesh.frag, phantom.frag and depth_only.frag (its cut-out variant).
struct MaterialUniforms {
    // Metallic-roughness: the base colour; Lafortune: rho_d (rgb).
    glm::vec4 baseColorFactor{1.0f};
    // xyz: emissive factor; w: normal-map scale (0 when there is no normal map, which
    // leaves the flat default texture's normal exactly unchanged).
    glm::vec4 emissiveNormalScale{0.0f};
    // x: metallic factor, y: roughness factor, z: 1 = Lafortune parameters below (0 = the
    // shader converts metallic-roughness per texel), w: the Fresnel parameter phi.
    glm::vec4 metallicRoughness{1.0f, 1.0f, 0.0f, 0.0f};
    // rgb: rho_s; w: tangent rotation / pi (x the rotation texture's red).
    glm::vec4 specularFactor{0.04f, 0.04f, 0.04f, 0.0f};
    // xyz: C_x, C_y, C_z; w: the exponent n.
    glm::vec4 lobeFactor{-1.0f, -1.0f, 1.0f, 64.0f};
    // 1 where the material has the texture, 0 where the shader may skip the lookup (the
    // factor alone): x base colour, y metallic-roughness or specular, z lobe, w rotation.
    glm::vec4 textureFlags{0.0f};
    // x: alpha mode (0 opaque, 1 mask, 2 blend); y: alpha cutoff (mask); z: 1 = unlit
    // (KHR_materials_unlit); w: occlusion strength (0 where there is no occlusion texture).
    glm::vec4 alphaUnlitOcclusion{0.0f, 0.5f, 0.0f, 0.0f};
    // Per texture slot (GltfTextureSlot order: base colour, metallic-roughness, normal,
    // emissive, occlusion, specular, lobe, tangent rotation) two rows of the uv transform:
    // uv' = (dot(row0.xyz, (u, v, 1)), dot(row1.xyz, (u, v, 1))), the uv set TEXCOORD_0, or
    // TEXCOORD_1 where row0.w is 1.
    glm::vec4 uvTransforms[16] = {{1, 0, 0, 0}, {0, 1, 0, 0}, {1, 0, 0, 0}, {0, 1, 0, 0}, {1, 0, 0, 0}, {0, 1, 0, 0},
                                  {1, 0, 0, 0}, {0, 1, 0, 0}, {1, 0, 0, 0}, {0, 1, 0, 0}, {1, 0, 0, 0}, {0, 1, 0, 0},
                                  {1, 0, 0, 0}, {0, 1, 0, 0}, {1, 0, 0, 0}, {0, 1, 0, 0}};
    // Light through the surface (GltfTransmission): x: the factor (0: none), y: 1 / ior, the
    // bend at the surface (1: thin-walled, or ior 0), z: the dielectric F0 of the ior, w: 1 =
    // a transmission texture (its red x the factor).
    glm::vec4 transmission{0.0f, 1.0f, 0.04f, 0.0f};
    // rgb: the tint of the light through (base colour or white, times the volume's
    // attenuation over its thickness); w: unused.
    glm::vec4 transmissionTint{1.0f};
    // The transmission texture's uv transform, as uvTransforms' rows.
    glm::vec4 transmissionUv[2] = {{1, 0, 0, 0}, {0, 1, 0, 0}};
};
static_assert(offsetof(MaterialUniforms, baseColorFactor) == 0);
static_assert(offsetof(MaterialUniforms, emissiveNormalScale) == 16);
static_assert(offsetof(MaterialUniforms, metallicRoughness) == 32);
static_assert(offsetof(MaterialUniforms, specularFactor) == 48);
static_assert(offsetof(MaterialUniforms, lobeFactor) == 64);
static_assert(offsetof(MaterialUniforms, textureFlags) == 80);
static_assert(offsetof(MaterialUniforms, alphaUnlitOcclusion) == 96);
static_assert(offsetof(MaterialUniforms, uvTransforms) == 112);
static_assert(offsetof(MaterialUniforms, transmission) == 368);
static_assert(sizeof(MaterialUniforms) == 432);

} // namespace lumar
