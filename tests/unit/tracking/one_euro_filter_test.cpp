// The pose filter against synthetic motion with seeded noise: it removes jitter from a still
// marker, follows a moving one with a small lag, and prediction shrinks that lag.
#include <cmath>
#include <random>

#include <glm/gtc/quaternion.hpp>
#include <gtest/gtest.h>

#include "tracking/one_euro_filter.h"
#include "tracking_test_support.h"

namespace lumar {
namespace {

constexpr int64_t kFrameNs = 33'333'333; // 30 fps

glm::dmat3 rotationAboutZ(double angle)
{
    return test::axisAngle({0, 0, 1}, angle);
}

struct Noise {
    std::mt19937 rng{7};
    std::normal_distribution<double> translation{0.0, 0.001}; // 1 mm
    std::normal_distribution<double> rotation{0.0, test::radians(0.3)};
    Pose apply(const Pose& truth)
    {
        Pose p = truth;
        p.t += glm::dvec3(translation(rng), translation(rng), translation(rng));
        const glm::dvec3 axis = glm::normalize(glm::dvec3(rotation(rng), rotation(rng), rotation(rng)) + 1e-12);
        p.R = test::axisAngle(axis, std::abs(rotation(rng)) * std::sqrt(3.0)) * p.R;
        return p;
    }
};

double rotationErrorDeg(const glm::dmat3& a, const glm::dmat3& b)
{
    return test::degrees(test::rotationErrorRad(a, b));
}

TEST(OneEuroPoseFilter, RemovesJitterFromAStillMarker)
{
    const Pose truth{rotationAboutZ(0.3), {0.05, -0.02, 0.6}};
    Noise noise;
    OneEuroPoseFilter filter;
    double rawT = 0, filteredT = 0, rawR = 0, filteredR = 0;
    int n = 0;
    for (int k = 0; k < 300; ++k) {
        const Pose measured = noise.apply(truth);
        const Pose filtered = filter.update(measured, k * kFrameNs);
        if (k < 30)
            continue; // settle
        rawT += std::pow(glm::length(measured.t - truth.t), 2);
        filteredT += std::pow(glm::length(filtered.t - truth.t), 2);
        rawR += std::pow(rotationErrorDeg(measured.R, truth.R), 2);
        filteredR += std::pow(rotationErrorDeg(filtered.R, truth.R), 2);
        ++n;
    }
    const double translationGain = std::sqrt(rawT / filteredT), rotationGain = std::sqrt(rawR / filteredR);
    RecordProperty("translation_jitter_reduction", std::to_string(translationGain));
    RecordProperty("rotation_jitter_reduction", std::to_string(rotationGain));
    EXPECT_GT(translationGain, 3.0); // measured 3.6
    EXPECT_GT(rotationGain, 3.0);    // measured 3.7
}

TEST(OneEuroPoseFilter, FollowsMotionWithSmallLagAndPredictionReducesIt)
{
    // 0.3 m/s sideways while turning at 60 deg/s.
    auto truthAt = [](int64_t ns) {
        const double t = double(ns) * 1e-9;
        return Pose{rotationAboutZ(test::radians(60.0) * t), {-0.3 + 0.3 * t, 0.0, 0.7}};
    };
    OneEuroPoseFilter filter;
    double worstLagM = 0, worstLagDeg = 0, worstPredictedM = 0, worstPredictedDeg = 0;
    for (int k = 0; k < 60; ++k) {
        const int64_t ns = k * kFrameNs;
        const Pose filtered = filter.update(truthAt(ns), ns);
        if (k < 20)
            continue;
        worstLagM = std::max(worstLagM, glm::length(filtered.t - truthAt(ns).t));
        worstLagDeg = std::max(worstLagDeg, rotationErrorDeg(filtered.R, truthAt(ns).R));
        // One frame ahead, as a renderer presenting at the next vsync would ask.
        const Pose predicted = filter.predict(ns + kFrameNs);
        worstPredictedM = std::max(worstPredictedM, glm::length(predicted.t - truthAt(ns + kFrameNs).t));
        worstPredictedDeg = std::max(worstPredictedDeg, rotationErrorDeg(predicted.R, truthAt(ns + kFrameNs).R));
    }
    RecordProperty("lag_mm", std::to_string(1000 * worstLagM));
    RecordProperty("lag_deg", std::to_string(worstLagDeg));
    EXPECT_LT(worstLagM, 0.005); // measured 3.2 mm
    EXPECT_LT(worstLagDeg, 1.5); // measured 0.85 deg
    // Without prediction the pose shown one frame later would be off by the lag plus a frame
    // of motion (10 mm, 2 deg); with it, by less than the lag alone.
    EXPECT_LT(worstPredictedM, worstLagM);
    EXPECT_LT(worstPredictedDeg, worstLagDeg);
}

TEST(OneEuroPoseFilter, ResetsAfterAGapAndOnTimeGoingBackwards)
{
    OneEuroPoseFilter filter;
    const Pose a{rotationAboutZ(0.0), {0, 0, 0.5}};
    const Pose b{rotationAboutZ(1.0), {0.2, 0, 0.5}};
    filter.update(a, 0);
    filter.update(a, kFrameNs);
    const Pose afterGap = filter.update(b, kFrameNs + 600'000'000);
    EXPECT_NEAR(glm::length(afterGap.t - b.t), 0.0, 1e-12);
    const Pose backwards = filter.update(a, 0);
    EXPECT_NEAR(glm::length(backwards.t - a.t), 0.0, 1e-12);
}

TEST(OneEuroPoseFilter, QuaternionSignDoesNotSwingTheOutput)
{
    // Rotations near 180 degrees, where quat_cast may return q or -q from frame to frame.
    OneEuroPoseFilter filter;
    double worst = 0;
    for (int k = 0; k < 30; ++k) {
        const Pose measured{rotationAboutZ(test::radians(179.5 + (k % 2))), {0, 0, 0.5}};
        const Pose filtered = filter.update(measured, k * kFrameNs);
        worst = std::max(worst, rotationErrorDeg(filtered.R, rotationAboutZ(test::radians(180.0))));
        // Always a proper rotation.
        const glm::dmat3 shouldBeIdentity = glm::transpose(filtered.R) * filtered.R;
        for (int i = 0; i < 3; ++i)
            for (int j = 0; j < 3; ++j)
                EXPECT_NEAR(shouldBeIdentity[i][j], i == j ? 1.0 : 0.0, 1e-9);
        EXPECT_NEAR(glm::determinant(filtered.R), 1.0, 1e-9);
    }
    EXPECT_LT(worst, 1.0);
}

} // namespace
} // namespace lumar
