// The paper's Lafortune SBRDF parameters on the CPU (DESIGN.md §6.4): the conversion of a glTF
// metallic-roughness material, the named presets the sidecar TOML offers, the value ranges
// the extension and the sidecar enforce, and the swirl tangent-rotation texture. The GLES
// shader converts metallic-roughness texels with the same formulas and constants.
#pragma once

#include <optional>
#include <span>
#include <string_view>

#include <glm/glm.hpp>

#include "core/image.h"
#include "gles_renderer/assets/gltf_model.h"

namespace lumar {

// Largest Phong/Lafortune exponent: a mirror (roughness 0) maps here instead of infinity.
// At 4096 the lobe's half-width (0.018 rad) is about 1.5 texels of a 128-pixel cube face, so
// sharper lobes would look the same as the mirror map.
inline constexpr float kMaxLafortuneExponent = 4096.0f;
// Smallest exponent the extension and the sidecar accept; roughness 1 converts to it.
inline constexpr float kMinLafortuneExponent = 1.0f;
// phi of the paper's Fresnel factor f = (1 - R.N)^(1/phi - 1): 1/6 makes the exponent 5, so
// rho_s + (1 - rho_s) f is exactly Schlick's approximation with F0 = rho_s.
inline constexpr float kMetallicRoughnessFresnelPhi = 1.0f / 6.0f;
// F0 of a dielectric (index of refraction 1.5), glTF's specular reflectance for metallic 0.
inline constexpr float kDielectricSpecular = 0.04f;
// |C_x|, |C_y|, |C_z| limit of the extension and the sidecar. Coefficients above 1 make the
// lobe magnitude |(C_x v_x, C_y v_y, C_z v_z)|^n exceed 1 (energy gain) at some angles; a
// little headroom lets artists compensate a lobe texture, but past 4 it is only overflow.
inline constexpr float kMaxLobeCoefficient = 4.0f;

// glTF metallic-roughness to Lafortune: alpha = roughness^2, n = 2/alpha^2 - 2 clamped to
// [kMinLafortuneExponent, kMaxLafortuneExponent]; rho_d = base (1 - metallic);
// rho_s = mix(kDielectricSpecular, base, metallic); Phong mirror lobe (-1, -1, 1);
// phi = kMetallicRoughnessFresnelPhi (Schlick); no tangent rotation. Inputs are clamped to
// [0, 1].
LafortuneParams lafortuneFromMetallicRoughness(glm::vec3 baseColor, float metallic, float roughness);

// Named parameter sets (chrome, brushed_metal, car_paint, rubber, plastic, glass, thin_glass,
// emissive);
// nothing for an unknown name. Every preset keeps rho_d + rho_s <= 1 per channel and
// |C_i| <= 1, so it reflects no more energy than it receives.
std::optional<LafortuneParams> materialPreset(std::string_view name);
// Light the `emissive` preset gives a material that emits nothing of its own (a built-in
// shape, a plain glTF material): linear radiance 4, white, so that with the lens's default
// threshold (1) it feeds the bloom with 3 above it. A material that already emits (glTF's
// emissiveFactor x KHR_materials_emissive_strength) keeps its own light under the preset.
inline constexpr float kEmissivePresetRadiance = 4.0f;
// The emission a preset lends a material without its own: kEmissivePresetRadiance for
// "emissive", black for every other preset and for unknown names.
glm::vec3 materialPresetEmission(std::string_view name);
// What light a preset lets through the surface: the `glass` preset is solid clear glass of
// index 1.5 (refracting, untinted), `thin_glass` a thin-walled pane of it (thickness 0: the
// view goes straight through); every other preset none (factor 0).
GltfTransmission materialPresetTransmission(std::string_view name);
// All preset names, in a stable order (for error messages and documentation).
std::span<const std::string_view> materialPresetNames();
// True for presets meant to be used with the swirl tangent-rotation texture (brushed_metal):
// the sidecar then attaches makeSwirlRotationTexture unless the entry names another texture.
bool materialPresetUsesSwirlRotation(std::string_view name);

// size x size RGBA texture of concentric brushing around the image centre. Texel (col, row)
// (row 0 at the top, glTF's uv origin) sits at x = col + 0.5 - c, y = c - (row + 0.5),
// c = size/2, with y pointing up the image, i.e. along -v, which is the direction of the
// bitangent B = w (N x T) (tangent_space.h). It holds the angle of the circle's tangent,
// angle = atan2(y, x) + pi/2 wrapped into [0, pi), measured from T towards B, as
// a = angle/pi stored round(a * 255) in r = g = b, alpha 255. The shader's rotation
// T' = T cos(a pi) + B sin(a pi) then follows the circles; with N x T in place of B the
// pattern is right only where the uvs are not mirrored (w = +1). Throws InputError for
// size < 1 or > 16384.
Image8 makeSwirlRotationTexture(int size);

} // namespace lumar
