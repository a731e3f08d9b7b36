// How the real environment map is turned relative to the table. The marker frame (and the
// fake camera's world frame, its translation) is Z up (core/pose.h); the equirectangular
// environment map is +Y up (gles_renderer/assets/environment_map.h). The renderer lights
// virtual objects and the fake camera draws its surroundings through this one rotation, so
// the world the camera shows is the one the objects are lit by.
#pragma once

#include <glm/glm.hpp>

namespace lumar {

// Rotation taking the marker frame (Z up) to the environment map's frame (+Y up), so the
// real environment stays fixed to the table.
glm::dmat3 environmentFromMarker();

} // namespace lumar
