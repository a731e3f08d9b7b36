// What a material and a view need of shaders_es/mesh.frag, as the bits that select a variant
// of it. llvmpipe runs both sides of every branch, uniform ones included: a texture lookup
// a material does not need costs as much as one it does unless the compiler removes it, so
// MeshPass links one variant per combination in use. On llvmpipe this took the car scene's
// objects from 43 to 24-27 ms of rendering CPU per frame without shadows, 45-48 to 36-41
// with them (lumar bench --replay, stages_cpu_ms.shading, two runs each, load 15-21).
#pragma once

#include <cstdint>
#include <string>

#include "gles_renderer/scene/uniform_blocks.h"

namespace lumar {

namespace mesh_feature {
// Of the material (GpuMaterial::features).
inline constexpr uint32_t kBaseColorTexture = 1U << 0;
inline constexpr uint32_t kSecondTexture = 1U << 1; // rho_s (Lafortune) or metallic-roughness
inline constexpr uint32_t kLobeTexture = 1U << 2;
inline constexpr uint32_t kRotationTexture = 1U << 3;
inline constexpr uint32_t kLafortune = 1U << 4;
inline constexpr uint32_t kNormalMap = 1U << 5;
inline constexpr uint32_t kEmission = 1U << 6;
inline constexpr uint32_t kOcclusionTexture = 1U << 10;
inline constexpr uint32_t kUnlit = 1U << 11;
inline constexpr uint32_t kAlphaMask = 1U << 12;    // glTF alphaMode MASK
inline constexpr uint32_t kAlphaBlend = 1U << 13;   // BLEND (neither: OPAQUE)
inline constexpr uint32_t kTransmission = 1U << 14; // light through the surface (glass)
// The least glossiness the material's lobe can have (glossFeatures): at least 1/4 leaves the
// diffuse map out of the glossy blend, 1/2 the glossy-1 map too, 1 (a mirror) the glossy-2 map.
inline constexpr uint32_t kGlossQuarter = 1U << 15;
inline constexpr uint32_t kGlossHalf = 1U << 16;
inline constexpr uint32_t kGlossMirror = 1U << 17;
// What the material's reflectance leaves out (reflectanceFeatures): with rho_d = 0 (metals,
// glass) no diffuse term, and with it no irradiance lookup and no shadow, which darkens only
// the diffuse term; without a tangent rotation no sine and cosine per pixel.
inline constexpr uint32_t kDiffuse = 1U << 18;
inline constexpr uint32_t kTangentRotation = 1U << 19;
// The lobe is Phong's (C = -1, -1, 1 everywhere: metallic-roughness, or Lafortune without a
// lobe texture): its peak is the mirror direction, no tangent frame needed.
inline constexpr uint32_t kPhongLobe = 1U << 20;
// Of the primitive (MeshPass): it has COLOR_0 or TEXCOORD_1 arrays (GpuPrimitive::extras).
// Without, mesh.frag reads the constants white and (0, 0) instead of interpolating them.
inline constexpr uint32_t kVertexExtras = 1U << 21;
// Of the view (viewFeatures).
inline constexpr uint32_t kShadow = 1U << 7;
inline constexpr uint32_t kRgbmMaps = 1U << 8;
// Bit 9 was WRITES_RADIANCE (a cube face of an environment map, not the frame): it only
// picks the output's encoding at the end of mesh.frag, so the uniform decides it. As a
// variant bit it linked every material twice (the frame's and the faces' program): 18
// programs instead of 9 for the car scene, whose peak RSS fell by ~10 MB on llvmpipe.
} // namespace mesh_feature

// The view's bits, from the frame's uniforms as mesh.frag would read them.
uint32_t viewFeatures(const FrameUniforms& frame);

// The material's glossiness bits (kGlossQuarter, kGlossHalf or kGlossMirror; 0 for none),
// from its uniforms. mesh.frag blends the four maps by the glossiness s' = s + (1 - s) f,
// never below the lobe's own s (the Fresnel factor f only raises it), and llvmpipe runs
// every lookup of the blend, weighted 0 or not: a floor known when the variant is linked
// leaves out the maps below it. The car scene's paint (n = 500), grille (200) and chrome
// (4096) read two maps, two and one instead of four.
uint32_t glossFeatures(const MaterialUniforms& material);

// kDiffuse where the material's diffuse reflectance is not 0 (mesh.frag's rho_d is the base
// colour factor times the texture, times 1 - metallic for metallic-roughness: a factor of 0
// makes it 0 whatever the texture), kTangentRotation where its Lafortune tangent rotation
// factor is not 0, kPhongLobe where the lobe is C = (-1, -1, 1) everywhere (metallic-roughness,
// or Lafortune without a lobe texture). On llvmpipe, which runs every lookup of a pixel
// whatever its weight, the car scene's chrome, glass and mirror ball skip the shadow's four
// taps and a map lookup, and every material but the grille its tangent frame.
uint32_t reflectanceFeatures(const MaterialUniforms& material);

// mesh.frag's #define lines fixing every feature to true or false.
std::string meshVariantDefines(uint32_t features);

} // namespace lumar
