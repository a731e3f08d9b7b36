// Rigid transforms between frames. A Pose named "camera_from_marker" maps a point given in
// the marker frame into the camera frame: p_cam = R * p_marker + t.
//
// The marker frame (used by the fake camera, the tracker and the renderer alike): origin
// at the tag's centre, x to the right and y up as the tag is seen printed upright, z out of
// the tag's face towards a viewer in front of it. The tag image's row 0 lies along the +y
// edge. In this frame the AprilTag library's corner order p[0..3] is
// (-s/2,-s/2), (+s/2,-s/2), (+s/2,+s/2), (-s/2,+s/2) for tag side s (black border to black
// border), i.e. counter-clockwise in the image as apriltag.h promises.
#pragma once

#include <array>

#include <glm/glm.hpp>

namespace lumar {

struct Pose {
    glm::dmat3 R{1.0};
    glm::dvec3 t{0.0};

    [[nodiscard]] glm::dvec3 apply(const glm::dvec3& p) const { return R * p + t; }
    [[nodiscard]] Pose inverse() const
    {
        const glm::dmat3 Rt = glm::transpose(R);
        return {Rt, -(Rt * t)};
    }
    [[nodiscard]] Pose operator*(const Pose& rhs) const { return {R * rhs.R, R * rhs.t + t}; }
    [[nodiscard]] glm::dmat4 matrix() const
    {
        glm::dmat4 m(R);
        m[3] = glm::dvec4(t, 1.0);
        return m;
    }
};

// Tag corners in the marker frame, in the AprilTag library's order (see above).
inline std::array<glm::dvec3, 4> tagCornersInMarkerFrame(double tagSize)
{
    const double h = 0.5 * tagSize;
    return {glm::dvec3{-h, -h, 0}, glm::dvec3{h, -h, 0}, glm::dvec3{h, h, 0}, glm::dvec3{-h, h, 0}};
}

} // namespace lumar
