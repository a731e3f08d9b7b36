// Pinhole camera model with OpenCV's conventions everywhere (DESIGN.md §5): camera frame
// x right, y down, z forward; pixel (0,0) covers [-0.5, 0.5]^2, so pixel centres sit at
// integer coordinates; distortion is OpenCV's (k1, k2, p1, p2, k3).
#pragma once

#include <array>
#include <cmath>

#include <glm/glm.hpp>

namespace lumar {

struct CameraIntrinsics {
    int width = 0;
    int height = 0;
    double fx = 0, fy = 0, cx = 0, cy = 0;
    std::array<double, 5> distortion{}; // k1 k2 p1 p2 k3

    // Projects a point in the camera frame (no distortion applied: the fake camera and
    // the renderer are ideal pinholes; real lenses are undistorted at the corners).
    [[nodiscard]] glm::dvec2 project(const glm::dvec3& p) const { return {fx * p.x / p.z + cx, fy * p.y / p.z + cy}; }
};

// The intrinsics the fake camera renders with and the default calibration matches:
// square pixels, principal point at the image centre, 70 degrees horizontal field of view.
inline CameraIntrinsics defaultIntrinsics(int width, int height)
{
    CameraIntrinsics k;
    k.width = width;
    k.height = height;
    const double horizontalFovHalf = 35.0 * 3.14159265358979323846 / 180.0;
    k.fx = k.fy = 0.5 * width / std::tan(horizontalFovHalf);
    k.cx = 0.5 * (width - 1);
    k.cy = 0.5 * (height - 1);
    return k;
}

} // namespace lumar
