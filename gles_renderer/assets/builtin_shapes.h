// Shapes generated in code, for scenes that need a clean sphere or box (the paper's mirror
// sphere beside a coloured object, test scenes) without shipping a file: an object's
// `model = "builtin:sphere"` in the configuration.
#pragma once

#include <string_view>

#include "gles_renderer/assets/gltf_model.h"

namespace lumar {

inline constexpr std::string_view kBuiltinModelPrefix = "builtin:";

// "sphere" or "cube".
bool isBuiltinShape(std::string_view name);

// A unit-diameter shape centred on the origin (glTF +Y up), one default material (white
// dielectric, roughness 0.5), normals, uvs and tangents. Throws InputError for an unknown name.
GltfModel makeBuiltinShape(std::string_view name);

// A UV sphere of radius 0.5 with `segments` around and `rings` from pole to pole.
GltfModel makeUvSphere(int segments, int rings);

// An axis-aligned cube of side 1, 24 vertices (flat faces).
GltfModel makeCube();

// A unit square in the plane y = 0 (x and z in [-0.5, 0.5]) facing +Y (glTF up), double-sided:
// a table top seen from above or below.
GltfModel makePlane();

// A closed cylinder of unit diameter and unit height, its axis along +Y (glTF up) from
// y = -0.5 to 0.5: `segments` around with smooth normals on the side, flat caps.
GltfModel makeCylinder(int segments = 48);

} // namespace lumar
