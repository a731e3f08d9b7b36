// Temporal filtering of a marker's pose (DESIGN.md §5): the One-Euro filter (Casiez, Roussel
// and Vogel, CHI 2012) on the translation, and the same speed-adaptive scheme on the rotation
// with slerp. A still marker is smoothed hard (the cutoff falls to minCutoffHz, jitter goes);
// a moving one follows quickly (the cutoff rises with speed, lag stays small).
#pragma once

#include <cstdint>

#include <glm/glm.hpp>
#include <glm/gtc/quaternion.hpp>

#include "core/pose.h"

namespace lumar {

// Defaults chosen by measurement (tests/unit/tracking/one_euro_filter_test.cpp, 30 fps, 1 mm /
// 0.3 degree noise): still-marker jitter divided by 3.6 (translation) and 3.7 (rotation), lag
// at 0.3 m/s and 60 deg/s of 3.2 mm and 0.85 degrees. The slow speed estimate (0.3 Hz) keeps
// noise from opening the cutoff; the price is a slower start when motion begins.
struct PoseFilterSettings {
    double minCutoffHz = 0.3;         // translation cutoff at rest
    double beta = 40;                 // cutoff increase per m/s
    double rotationMinCutoffHz = 0.3; // rotation cutoff at rest
    double rotationBeta = 8;          // cutoff increase per rad/s
    double derivativeCutoffHz = 0.3;  // smoothing of the speed estimates
    double resetAfterS = 0.5;         // a longer gap starts afresh from the measurement
};

class OneEuroPoseFilter {
public:
    explicit OneEuroPoseFilter(PoseFilterSettings settings = {}) : settings_(settings) {}

    // Feeds a measurement taken at `timestampNs`; returns the filtered pose. The first
    // sample, a timestamp not after the previous one, or a gap over resetAfterS resets.
    Pose update(const Pose& measured, int64_t timestampNs);

    // The filtered pose extrapolated with the filtered velocities to `timestampNs` (at most
    // kMaxPredictionS ahead of the last update: beyond that, guessing does more harm).
    [[nodiscard]] Pose predict(int64_t timestampNs) const;

    void reset() { initialised_ = false; }
    [[nodiscard]] bool initialised() const { return initialised_; }

    static constexpr double kMaxPredictionS = 0.1;

private:
    PoseFilterSettings settings_;
    bool initialised_ = false;
    bool hasVelocity_ = false;
    int64_t lastNs_ = 0;
    glm::dvec3 position_{0.0};
    glm::dvec3 velocity_{0.0}; // filtered, m/s
    glm::dquat orientation_{1, 0, 0, 0};
    glm::dvec3 angularVelocity_{0.0}; // filtered, rad/s, world axis times rate
};

} // namespace lumar
