// glTF materials and the textures they use, converted to lumar's plain structures.
// Internal to lumar_assets: error messages carry no file name, the loader adds it.
#pragma once

#include <string>
#include <vector>

#include <tiny_gltf.h>

#include "gles_renderer/assets/gltf_model.h"

namespace lumar::gltf {

struct ConvertedMaterials {
    std::vector<GltfMaterial> materials; // one per glTF material, same order
    std::vector<GltfTexture> textures;   // only the images some material uses
    std::vector<GltfSampler> samplers;   // parallel to textures
};

// metallic-roughness factors and textures, normal texture and scale, emissive factor (times
// KHR_materials_emissive_strength) and texture, doubleSided. An image used both as colour
// and as data becomes two textures (sRGB and linear). A texture whose image could not be
// loaded (say, a missing external file) is dropped with a warning; `fileForLog` names the
// model in those warnings. LUMAR_materials_lafortune (LUMAR_materials_lafortune.md) sets
// hasLafortune, the Lafortune parameters and their textures; a malformed field throws
// InputError naming the material (index and name) and the field.
ConvertedMaterials convertMaterials(const tinygltf::Model& model, const std::string& fileForLog);

} // namespace lumar::gltf
