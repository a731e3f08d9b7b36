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
// Read here, with the rest of the configuration, into the renderer's plain
// MaterialOverrides (gles_renderer/assets/material_overrides.h), which applies them.
#pragma once

#include <filesystem>

#include "gles_renderer/assets/material_overrides.h"

namespace lumar {

// Throws InputError "FILE:LINE: what is wrong" for a TOML syntax error, an unknown key, a
// wrong type, an unknown preset, a value out of range or a texture that cannot be read.
// Checks values against the ranges of LUMAR_materials_lafortune; a material name that matches
// nothing is found only when the overrides meet their model (applyMaterialOverrides).
MaterialOverrides loadMaterialSidecar(const std::filesystem::path& file);

} // namespace lumar
