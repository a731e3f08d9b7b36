#include "capture/fake_trajectory.h"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace lumar {
namespace {

constexpr double kDegrees = std::numbers::pi / 180.0;

// The radius of a default tag (16 cm, white frame included) seen from its centre: the
// orbit below is tuned for it and scaled up for larger layouts.
constexpr double kTagFrameToBorder = 10.0 / 8.0;
const double kDefaultLayoutRadius = 0.5 * 0.16 * kTagFrameToBorder * std::sqrt(2.0);

} // namespace

FakeTrajectory::FakeTrajectory(const std::vector<FakeTagConfig>& tags)
{
    if (tags.empty()) {
        return;
    }
    for (const auto& tag : tags) {
        centre_ += tag.position;
    }
    centre_ /= double(tags.size());
    double radius = 0.0;
    for (const auto& tag : tags) {
        const double corner = 0.5 * tag.size * kTagFrameToBorder * std::sqrt(2.0);
        radius = std::max(radius, glm::length(tag.position - centre_) + corner);
    }
    scale_ = std::max(1.0, radius / kDefaultLayoutRadius);
}

Pose FakeTrajectory::cameraFromWorld(double seconds) const
{
    // Every term's frequency is a whole multiple of the base, so the path repeats exactly.
    const double phase = 2.0 * std::numbers::pi * seconds / kPeriodSeconds;
    const double distance = scale_ * (0.65 + 0.15 * std::sin(phase + 0.5));
    const double elevation = (52.5 + 12.5 * std::sin(2.0 * phase + 1.0)) * kDegrees;
    const double azimuth = (-90.0 + 45.0 * std::sin(phase)) * kDegrees;
    const double roll = 4.0 * kDegrees * std::sin(3.0 * phase + 2.1);
    const glm::dvec3 wander = scale_ * 0.03 * glm::dvec3(std::sin(3.0 * phase + 0.4), std::sin(2.0 * phase + 1.3), 0.0);

    const glm::dvec3 centre(centre_, 0.0);
    const glm::dvec3 eye = centre + distance * glm::dvec3(std::cos(elevation) * std::cos(azimuth),
                                                          std::cos(elevation) * std::sin(azimuth), std::sin(elevation));
    const glm::dvec3 target = centre + wander;

    // Camera axes in world coordinates (OpenCV: x right, y down, z forward). The elevation
    // stays below 65°, so forward is never parallel to world up.
    const glm::dvec3 forward = glm::normalize(target - eye);
    const glm::dvec3 levelRight = glm::normalize(glm::cross(forward, glm::dvec3(0.0, 0.0, 1.0)));
    const glm::dvec3 levelDown = glm::cross(forward, levelRight);
    const glm::dvec3 right = std::cos(roll) * levelRight + std::sin(roll) * levelDown;
    const glm::dvec3 down = glm::cross(forward, right);

    Pose cameraFromWorld;
    // R's rows are the camera axes in world coordinates (glm is column-major: [col][row]).
    for (int i = 0; i < 3; ++i) {
        cameraFromWorld.R[i][0] = right[i];
        cameraFromWorld.R[i][1] = down[i];
        cameraFromWorld.R[i][2] = forward[i];
    }
    cameraFromWorld.t = -(cameraFromWorld.R * eye);
    return cameraFromWorld;
}

} // namespace lumar
