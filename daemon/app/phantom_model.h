// The model and placement of a configured phantom (config.h PhantomConfig, DESIGN.md §6.5).
//
//   box:      markerFromModel = T(offset) · Rz(heading) · S(size)             (the unit cube)
//   plane:    markerFromModel = T(offset) · Rz(heading) · S(size.x, size.y, 1) · Rx(+90°)
//   cylinder: markerFromModel = T(offset) · Rz(heading) · S(size) · Rx(+90°)
//   mesh:     app/object_placement.h's markerFromModel with offset, heading and size
//
// The built-in plane and cylinder are glTF-style, +Y up; Rx(+90°) stands them on the marker
// (+Y -> +Z), so the plane lies in the marker plane (facing +Z) and the cylinder's axis is the
// marker's normal. Box, plane and cylinder are centred on `offset` (a table top under the tag
// is offset by half its thickness, as before shapes existed); a mesh stands on the plane
// z = offset.z like an object.
#pragma once

#include <glm/glm.hpp>

#include "config/config.h"
#include "gles_renderer/assets/gltf_model.h"

namespace lumar {

struct PhantomModel {
    GltfModel model; // one material: the configured colour, rough dielectric, no textures
    glm::dmat4 markerFromModel{1.0};
};

// Needs phantom.mesh for shape "mesh" (loadConfig reads it).
PhantomModel makePhantomModel(const PhantomConfig& phantom);

} // namespace lumar
