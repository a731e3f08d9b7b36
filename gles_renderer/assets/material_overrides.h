// Lafortune material overrides for a loaded model, as plain data: what a sidecar file next to
// the model asks for (daemon/config/material_sidecar.h reads it) or what a scene's
// `material = "preset"` asks for every material. The renderer applies them; it reads no
// configuration file itself.
//
// Without a preset an entry starts from the material's own Lafortune parameters (from the
// extension) or, for a plain material, from lafortuneFromMetallicRoughness of its factors.
// Ranges are the extension's (LUMAR_materials_lafortune.md); the reader enforces them.
#pragma once

#include <map>
#include <optional>
#include <string>

#include <glm/glm.hpp>

#include "core/image.h"
#include "gles_renderer/assets/gltf_model.h"

namespace lumar {

struct MaterialOverride {
    int line = 0;                         // of the entry in its source file, for messages
    std::optional<std::string> preset;    // a name materialPreset() knows
    std::optional<glm::vec3> diffuse;     // rho_d, linear, each in [0, 1]
    std::optional<glm::vec3> specular;    // rho_s, linear, each in [0, 1]
    std::optional<glm::vec3> lobe;        // C_x, C_y, C_z, |C_i| <= kMaxLobeCoefficient, not all 0
    std::optional<float> exponent;        // n in [kMinLafortuneExponent, kMaxLafortuneExponent]
    std::optional<float> fresnelPhi;      // [0, 1)
    std::optional<float> tangentRotation; // [0, 1]
    // Unset: keep the material's texture (or the swirl when the preset asks for it).
    enum class RotationTexture { Unset, None, Swirl, Image };
    RotationTexture rotationTexture = RotationTexture::Unset;
    Image8 rotationImage; // RGBA (RotationTexture::Image)
};

struct MaterialOverrides {
    std::string source; // the file the overrides come from, for messages ("" when none)
    // By glTF material name; "*" is the entry for every material without its own.
    std::map<std::string, MaterialOverride, std::less<>> materials;
};

// Side of the generated texture tangent_rotation_texture = "swirl" attaches.
inline constexpr int kSwirlRotationTextureSize = 256;

// Sets hasLafortune and the parameters of every material the overrides name (and, with a "*"
// entry, of all others), appending the rotation textures they need to model.textures (linear,
// each at most once). Throws InputError "SOURCE:LINE: ..." naming an entry that matches no
// material and listing the model's material names; the model is then left unchanged.
void applyMaterialOverrides(GltfModel& model, const MaterialOverrides& overrides);

} // namespace lumar
