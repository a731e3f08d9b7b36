// Cheap stand-ins for the environment maps: a primitive simplified by vertex clustering
// (Rossignac & Borrel 1993). Every vertex snaps to a cell of a regular grid; the cell's
// vertex is the mean of those in it; triangles that collapse are dropped. A neighbour seen
// in a 64-pixel cube face spans tens of pixels, so a grid of about as many cells along the
// model loses nothing visible there and removes most of the triangles.
#pragma once

#include <glm/glm.hpp>

#include "gles_renderer/assets/gltf_model.h"

namespace lumar {

// `cellSize`: the grid step in the primitive's own (mesh) coordinates, > 0. Returns a
// primitive with the same material and transform; normals and tangents averaged and
// renormalised, uvs averaged (textures on stand-ins only need to be roughly right).
GltfPrimitive simplifyByClustering(const GltfPrimitive& primitive, float cellSize);

// A stand-in for the whole model with about `cellsAlongLongestSide` cells along the longest
// side of its bounds (in model space; each primitive's grid accounts for its transform's scale).
GltfModel makeProxyModel(const GltfModel& model, int cellsAlongLongestSide);

} // namespace lumar
