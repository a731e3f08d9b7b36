// Cheap stand-ins for the environment maps: a primitive simplified by meshoptimizer's
// error-bounded edge collapse (meshopt_simplify, quadric error metric; Debian's 0.18).
// Vertices keep their positions and attributes (a collapse moves a vertex onto a
// neighbour, never to an average), borders and uv/normal seams stay closed, and the
// collapses stop where the error bound would be passed. A neighbour seen in a 64-pixel cube
// face spans tens of pixels, so an error well under a pixel loses nothing visible there
// and removes most of the triangles of a dense mesh. Vertices where several seams meet are
// not collapsed in 0.18, so a mesh split into many flat-shaded pieces (CesiumMilkTruck)
// keeps most of its triangles.
#pragma once

#include "gles_renderer/assets/gltf_model.h"

namespace lumar {

// `maxError`: meshoptimizer's error bound in the primitive's own (mesh) coordinates, > 0:
// about how far the simplified surface may stray from the original (a quadric error, so a
// single vertex may stray a few times further; see makeProxyModel). Returns a primitive
// with the same material and transform holding only the vertices its triangles use.
// Throws InputError for mismatched attribute arrays or indices that are not whole
// triangles within the vertices.
GltfPrimitive simplifyPrimitive(const GltfPrimitive& primitive, float maxError);

// A stand-in for the whole model whose surface stays within a "cell", 1/`cellsAlongLongestSide`
// of the longest side of its bounds (in model space; each primitive's bound accounts for its
// transform's scale): the level semantics of the vertex clustering grid this replaced.
GltfModel makeProxyModel(const GltfModel& model, int cellsAlongLongestSide);

// makeProxyModel's primitives alone, in the model's order: what the stand-ins upload. Without
// a copy of the model's materials and decoded textures, which for CesiumMilkTruck's 2048²
// image was 16 MB per stand-in level, transient at load but the car scene's peak (issue 18).
std::vector<GltfPrimitive> makeProxyPrimitives(const GltfModel& model, int cellsAlongLongestSide);

} // namespace lumar
