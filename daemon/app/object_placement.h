// Where a configured object sits on its marker. glTF models are Y-up with arbitrary origins;
// the marker frame is Z-up (core/pose.h). A model is stood on the marker: its bounding box is
// centred on the marker's origin in x/y with its lowest point on the tag's plane, turned so
// model +Y becomes marker +Z, scaled (`size` fits the longest side), then rotated and offset
// as the config says.
#pragma once

#include <glm/glm.hpp>

#include "config/config.h"

namespace lumar {

glm::dmat4 markerFromModel(const ObjectConfig& object, const glm::vec3& boundsMin, const glm::vec3& boundsMax);

// Rotation taking the marker frame (Z up) to the environment map's frame (+Y up,
// gles_renderer/assets/environment_map.h), so the real environment stays fixed to the table.
glm::dmat3 environmentFromMarker();

} // namespace lumar
