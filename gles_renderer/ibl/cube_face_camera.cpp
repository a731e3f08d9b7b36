#include "gles_renderer/ibl/cube_face_camera.h"

#include <array>

namespace lumar {

glm::dmat3 faceCameraFromCube(int face)
{
    // (s axis, t axis, major axis) per face, from the spec's table: for +X, sc = -z and
    // tc = -y, so s grows along -Z and t along -Y.
    struct Axes {
        glm::dvec3 s, t, major;
    };
    static const std::array<Axes, kCubeFaces> kAxes{{
        {{0, 0, -1}, {0, -1, 0}, {1, 0, 0}},
        {{0, 0, 1}, {0, -1, 0}, {-1, 0, 0}},
        {{1, 0, 0}, {0, 0, 1}, {0, 1, 0}},
        {{1, 0, 0}, {0, 0, -1}, {0, -1, 0}},
        {{1, 0, 0}, {0, -1, 0}, {0, 0, 1}},
        {{-1, 0, 0}, {0, -1, 0}, {0, 0, -1}},
    }};
    const Axes& a = kAxes[size_t(face)];
    // Columns are the face camera's axes in cube coordinates; its transpose maps back.
    return glm::transpose(glm::dmat3(a.s, a.t, a.major));
}

CameraIntrinsics faceIntrinsics(int size)
{
    CameraIntrinsics k;
    k.width = size;
    k.height = size;
    k.fx = k.fy = 0.5 * size;
    k.cx = k.cy = 0.5 * size - 0.5;
    return k;
}

} // namespace lumar
