#include "tracking/one_euro_filter.h"

#include <algorithm>
#include <cmath>

namespace lumar {
namespace {

constexpr double kPi = 3.14159265358979323846;

// The exponential smoothing factor of a first-order low-pass at `cutoffHz` for a step `dt`.
double smoothing(double cutoffHz, double dt)
{
    const double tau = 1.0 / (2.0 * kPi * cutoffHz);
    return 1.0 / (1.0 + tau / dt);
}

// Rotation vector (axis times angle) of a unit quaternion, shortest way round.
glm::dvec3 rotationVector(glm::dquat q)
{
    if (q.w < 0)
        q = -q;
    const double s = std::sqrt(std::max(0.0, 1.0 - q.w * q.w));
    const double angle = 2.0 * std::atan2(s, q.w);
    if (s < 1e-12)
        return 2.0 * glm::dvec3(q.x, q.y, q.z);
    return glm::dvec3(q.x, q.y, q.z) * (angle / s);
}

glm::dquat fromRotationVector(const glm::dvec3& v)
{
    const double angle = glm::length(v);
    if (angle < 1e-12)
        return glm::normalize(glm::dquat(1.0, 0.5 * v.x, 0.5 * v.y, 0.5 * v.z));
    return glm::angleAxis(angle, v / angle);
}

} // namespace

Pose OneEuroPoseFilter::update(const Pose& measured, int64_t timestampNs)
{
    glm::dquat q = glm::normalize(glm::quat_cast(measured.R));
    const double dt = double(timestampNs - lastNs_) * 1e-9;
    if (!initialised_ || dt <= 0.0 || dt > settings_.resetAfterS) {
        initialised_ = true;
        lastNs_ = timestampNs;
        position_ = measured.t;
        velocity_ = glm::dvec3(0.0);
        orientation_ = q;
        angularVelocity_ = glm::dvec3(0.0);
        hasVelocity_ = false;
        return measured;
    }
    lastNs_ = timestampNs;
    // The second sample gives the first speed estimate; starting the estimate from zero instead
    // would hold the cutoff at its resting value for a whole derivative time constant and lag
    // behind a marker that was already moving.
    const bool firstStep = !hasVelocity_;
    hasVelocity_ = true;

    // Translation: the speed estimate is itself low-passed, then sets the cutoff.
    const glm::dvec3 rawVelocity = (measured.t - position_) / dt;
    velocity_ =
        firstStep ? rawVelocity : velocity_ + smoothing(settings_.derivativeCutoffHz, dt) * (rawVelocity - velocity_);
    const double cutoff = settings_.minCutoffHz + settings_.beta * glm::length(velocity_);
    position_ += smoothing(cutoff, dt) * (measured.t - position_);

    // Rotation: the same on the rotation from the filtered orientation to the measurement.
    if (glm::dot(q, orientation_) < 0.0)
        q = -q; // q and -q are the same rotation: take the near one
    const glm::dvec3 step = rotationVector(q * glm::inverse(orientation_));
    angularVelocity_ =
        firstStep ? step / dt
                  : angularVelocity_ + smoothing(settings_.derivativeCutoffHz, dt) * (step / dt - angularVelocity_);
    const double rotationCutoff =
        settings_.rotationMinCutoffHz + settings_.rotationBeta * glm::length(angularVelocity_);
    orientation_ = glm::normalize(glm::slerp(orientation_, q, smoothing(rotationCutoff, dt)));

    return {glm::mat3_cast(orientation_), position_};
}

Pose OneEuroPoseFilter::predict(int64_t timestampNs) const
{
    const double ahead = std::clamp(double(timestampNs - lastNs_) * 1e-9, 0.0, kMaxPredictionS);
    const glm::dquat q = glm::normalize(fromRotationVector(angularVelocity_ * ahead) * orientation_);
    return {glm::mat3_cast(q), position_ + velocity_ * ahead};
}

} // namespace lumar
