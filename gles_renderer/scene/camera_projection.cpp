#include "gles_renderer/scene/camera_projection.h"

namespace lumar {

glm::dmat4 clipFromCamera(const CameraIntrinsics& intrinsics, int width, int height, double nearZ, double farZ)
{
    // With w_clip = z: x_ndc = 2 (u + 0.5) / width - 1 where u = fx x / z + cx, so
    // x_clip = (2 fx / width) x + ((2 cx + 1) / width - 1) z; likewise for y.
    const double w = width;
    const double h = height;
    glm::dmat4 m(0.0); // column-major: m[column][row]
    m[0][0] = 2.0 * intrinsics.fx / w;
    m[2][0] = (2.0 * intrinsics.cx + 1.0) / w - 1.0;
    m[1][1] = 2.0 * intrinsics.fy / h;
    m[2][1] = (2.0 * intrinsics.cy + 1.0) / h - 1.0;
    m[2][2] = (farZ + nearZ) / (farZ - nearZ);
    m[3][2] = -2.0 * farZ * nearZ / (farZ - nearZ);
    m[2][3] = 1.0;
    return m;
}

} // namespace lumar
