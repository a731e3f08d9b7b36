// Lafortune material overrides from a TOML file next to a model, for models one cannot (or
// would rather not) edit to add LUMAR_materials_lafortune:
//
//   [material."*"]            # every material without its own entry (optional)
//   preset = "plastic"
//   [material."Body"]         # a glTF material name
//   preset = "car_paint"      # optional base; the fields below override it
//   diffuse = [0.5, 0.02, 0.02]
//   specular = [0.05, 0.05, 0.05]
//   lobe = [-1.0, -1.0, 1.0]
//   exponent = 500.0
//   fresnel_phi = 0.2
//   tangent_rotation = 0.0
//   tangent_rotation_texture = "swirl"   # "swirl", "none", or a PNG path relative to this file
//
// Without a preset an entry starts from the material's own Lafortune parameters (from the
// extension) or, for a plain material, from lafortuneFromMetallicRoughness of its factors.
// Ranges are the extension's (LUMAR_materials_lafortune.md).
#pragma once

#include <filesystem>
#include <map>
#include <optional>
#include <string>

#include <glm/glm.hpp>

#include "core/image.h"
#include "gles_renderer/gltf_model.h"

namespace lumar {

struct MaterialSidecarEntry {
    int line = 0;                         // of the entry's table, for messages
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
    Image8 rotationImage; // RGBA, decoded at load time (RotationTexture::Image)
};

struct MaterialSidecar {
    std::filesystem::path file;
    // By glTF material name; "*" is the entry for every material without its own.
    std::map<std::string, MaterialSidecarEntry, std::less<>> materials;
};

// Side of the generated texture tangent_rotation_texture = "swirl" attaches.
inline constexpr int kSidecarSwirlTextureSize = 256;

// Throws InputError "FILE:LINE: what is wrong" for a TOML syntax error, an unknown key, a
// wrong type, an unknown preset, a value out of range or a texture that cannot be read.
MaterialSidecar loadMaterialSidecar(const std::filesystem::path& file);

// Sets hasLafortune and the parameters of every material the sidecar names (and, with a "*"
// entry, of all others), appending the rotation textures it needs to model.textures (linear,
// each at most once). Throws InputError "FILE:LINE: ..." naming an entry that matches no
// material and listing the model's material names; the model is then left unchanged.
void applyMaterialSidecar(GltfModel& model, const MaterialSidecar& sidecar);

} // namespace lumar
