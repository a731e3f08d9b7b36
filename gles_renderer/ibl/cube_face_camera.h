// The six cameras of a cube map, in the OpenCV camera convention of the rest of the
// renderer (x right, y down, z forward): for face f, image x runs along the GL cube-map
// coordinate s, image y along t and z along the face's major axis (the OpenGL ES 3.0
// face-selection table). Cube maps are left-handed, so every face camera is mirrored:
// determinant -1, which the mesh pass sees and answers by flipping the winding.
#pragma once

#include <glm/glm.hpp>

#include "core/camera_model.h"

namespace lumar {

// Face order of GL_TEXTURE_CUBE_MAP_POSITIVE_X + f: +X, -X, +Y, -Y, +Z, -Z.
inline constexpr int kCubeFaces = 6;

// Rotation (with mirroring) from the cube map's frame to face f's camera frame.
glm::dmat3 faceCameraFromCube(int face);

// A 90-degree pinhole camera covering a size x size face exactly: pixel (u, v) is the texel
// whose centre direction clipFromCamera() puts there.
CameraIntrinsics faceIntrinsics(int size);

} // namespace lumar
