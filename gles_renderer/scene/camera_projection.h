// The projection that puts a point of the OpenCV camera frame exactly where the pinhole
// model puts it (core/camera_model.h): pixel centres at integer coordinates.
#pragma once

#include <glm/glm.hpp>

#include "core/camera_model.h"

namespace lumar {

inline constexpr double kNearPlaneMetres = 0.01;
inline constexpr double kFarPlaneMetres = 100.0;

// Clip space from the camera frame for a width x height framebuffer whose row y holds
// image row y (row 0 at window y = 0, so glReadPixels returns the top row first). A point
// X lands at window (u + 0.5, v + 0.5) with (u, v) = intrinsics.project(X), i.e. on the
// centre of pixel (u, v); depth maps [nearZ, farZ] to [-1, 1]. The image's y-down axis
// stays y-down in window coordinates, so front faces (counter-clockwise as seen in a
// right-handed frame) wind clockwise in the window: use glFrontFace(GL_CW).
glm::dmat4 clipFromCamera(const CameraIntrinsics& intrinsics, int width, int height, double nearZ = kNearPlaneMetres,
                          double farZ = kFarPlaneMetres);

} // namespace lumar
