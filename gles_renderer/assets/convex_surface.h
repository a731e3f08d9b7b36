// Whether a model's surface bounds a convex body (issue 18: ShadowPass's apply pass writes a
// phantom's depth itself, one full-resolution pass instead of two, where each pixel meets at
// most one of its front faces).
#pragma once

#include <cstddef>

#include "gles_renderer/assets/gltf_model.h"

namespace lumar {

// A model of more triangles is not tested (a box has 12, a built-in cylinder a few hundred):
// the test compares every corner with every triangle's plane.
inline constexpr size_t kConvexSurfaceMaxTriangles = 512;

// True where every corner of `model`'s triangles (model space: modelFromMesh applied, a
// mirroring one turning the winding back) lies on or behind the plane of every triangle,
// wound counter-clockwise seen from outside as glTF's front faces are: its front faces then
// cover any view's pixel at most once. False for no triangle, degenerate or non-finite
// corners, an inward winding, or more than kConvexSurfaceMaxTriangles.
bool isConvexSurface(const GltfModel& model);

} // namespace lumar
