// Shared helpers of the tracking tests: OpenCV <-> lumar conversions, reference projections
// with OpenCV (independent of the code under test) and pose comparisons.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

#include <glm/glm.hpp>
#include <opencv2/calib3d.hpp>
#include <opencv2/core.hpp>

#include "core/camera_model.h"
#include "core/image.h"
#include "core/pose.h"

namespace lumar::test {

inline constexpr double kPi = 3.14159265358979323846;
inline double degrees(double radians)
{
    return radians * 180.0 / kPi;
}
inline double radians(double degrees)
{
    return degrees * kPi / 180.0;
}

// A pinhole camera without distortion, the principal point at the image's centre.
inline CameraIntrinsics pinholeCamera(int width, int height, double focalPx)
{
    CameraIntrinsics k;
    k.width = width;
    k.height = height;
    k.fx = k.fy = focalPx;
    k.cx = (width - 1) / 2.0;
    k.cy = (height - 1) / 2.0;
    return k;
}

inline Image8 toImage8(const cv::Mat& gray)
{
    Image8 image(gray.cols, gray.rows, 1);
    for (int y = 0; y < gray.rows; ++y)
        for (int x = 0; x < gray.cols; ++x)
            *image.at(x, y) = gray.at<uint8_t>(y, x);
    return image;
}

// Rotation by `angle` radians about the unit `axis` (Rodrigues' formula through OpenCV).
inline glm::dmat3 axisAngle(const glm::dvec3& axis, double angle)
{
    const glm::dvec3 a = glm::normalize(axis) * angle;
    cv::Matx33d m;
    cv::Rodrigues(cv::Vec3d(a.x, a.y, a.z), m);
    glm::dmat3 r;
    for (int row = 0; row < 3; ++row)
        for (int col = 0; col < 3; ++col)
            r[col][row] = m(row, col);
    return r;
}

// A tag facing the camera upright (marker x right, y up in the image, z towards the
// camera), then rotated in its plane by `inPlane` and tilted by `tilt` about the in-plane
// axis at angle `tiltAxis` from marker x; centred at `t` in the camera frame.
inline Pose tagPose(double inPlane, double tilt, double tiltAxis, const glm::dvec3& t)
{
    const glm::dmat3 facingCamera(glm::dvec3(1, 0, 0), glm::dvec3(0, -1, 0), glm::dvec3(0, 0, -1));
    const glm::dmat3 tiltR = axisAngle({std::cos(tiltAxis), std::sin(tiltAxis), 0.0}, tilt);
    const glm::dmat3 spin = axisAngle({0.0, 0.0, 1.0}, inPlane);
    return {facingCamera * tiltR * spin, t};
}

// Projects the tag's corners (AprilTag order, core/pose.h) with cv::projectPoints, which
// applies the lens distortion.
inline std::array<glm::dvec2, 4> projectTagCorners(const Pose& cameraFromMarker, double tagSize,
                                                   const CameraIntrinsics& k)
{
    std::vector<cv::Point3d> points;
    for (const glm::dvec3& corner : tagCornersInMarkerFrame(tagSize)) {
        const glm::dvec3 p = cameraFromMarker.apply(corner);
        points.emplace_back(p.x, p.y, p.z);
    }
    const cv::Matx33d K(k.fx, 0, k.cx, 0, k.fy, k.cy, 0, 0, 1);
    const std::vector<double> dist(k.distortion.begin(), k.distortion.end());
    std::vector<cv::Point2d> image;
    cv::projectPoints(points, cv::Vec3d(0, 0, 0), cv::Vec3d(0, 0, 0), K, dist, image);
    std::array<glm::dvec2, 4> corners;
    for (size_t i = 0; i < 4; ++i)
        corners[i] = {image[i].x, image[i].y};
    return corners;
}

// Angle of the rotation taking `a` to `b`, radians.
inline double rotationErrorRad(const glm::dmat3& a, const glm::dmat3& b)
{
    const glm::dmat3 d = glm::transpose(a) * b;
    const double c = std::clamp((d[0][0] + d[1][1] + d[2][2] - 1.0) / 2.0, -1.0, 1.0);
    // acos loses precision near 0; use the antisymmetric part's norm there.
    const double s = 0.5 * glm::length(glm::dvec3(d[1][2] - d[2][1], d[2][0] - d[0][2], d[0][1] - d[1][0]));
    return std::atan2(s, c);
}

} // namespace lumar::test
