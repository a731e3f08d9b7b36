// solveTagPose against synthetic projections: corners of a tag with a known pose projected
// with OpenCV's projectPoints (with and without lens distortion), exact and with noise.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <random>
#include <vector>

#include <gtest/gtest.h>

#include "tracking/tag_tracker.h"
#include "tracking_test_support.h"

namespace lumar {
namespace {

using test::degrees;
using test::projectTagCorners;
using test::radians;
using test::rotationErrorRad;
using test::tagPose;

constexpr double kTagSize = 0.16;

// OpenCV's own calibration of its left*.jpg samples (tests/data/calib/chessboard/
// left_intrinsics.yml): strong barrel distortion, a realistic lens.
CameraIntrinsics distortedCamera()
{
    CameraIntrinsics k;
    k.width = 640;
    k.height = 480;
    k.fx = k.fy = 535.91573396163199;
    k.cx = 342.28315473308373;
    k.cy = 235.57082909788173;
    k.distortion = {-0.26637260909660682, -0.038588898922304653, 0.0017831947042852964, -0.00028122100441115472,
                    0.23839153080878486};
    return k;
}

struct PoseCase {
    double distance, tiltDeg, spinDeg;
    Pose truth;
};

bool insideImage(const std::array<glm::dvec2, 4>& corners, const CameraIntrinsics& k)
{
    return std::all_of(corners.begin(), corners.end(), [&](const glm::dvec2& c) {
        return c.x >= 0.0 && c.y >= 0.0 && c.x <= k.width - 1.0 && c.y <= k.height - 1.0;
    });
}

// Tags at `distances`, tilted by `tilts` about a varying in-plane axis, turned in their plane
// by several angles and shifted off the optical axis; only those wholly inside the image
// (a 16 cm tag turned by 37 degrees at 0.3 m does not fit in 720 rows).
std::vector<PoseCase> poseGrid(const CameraIntrinsics& k, std::initializer_list<double> distances,
                               std::initializer_list<double> tilts)
{
    std::vector<PoseCase> cases;
    int index = 0;
    for (double d : distances)
        for (double tilt : tilts)
            for (double spin : {0.0, 37.0, 150.0, 260.0}) {
                const double a = 0.7 * ++index;
                const glm::dvec3 t{0.1 * d * std::cos(a), 0.06 * d * std::sin(a), d};
                const Pose truth = tagPose(radians(spin), radians(tilt), a, t);
                if (insideImage(projectTagCorners(truth, kTagSize, k), k))
                    cases.push_back({d, tilt, spin, truth});
            }
    return cases;
}

double relativeTranslationError(const Pose& truth, const Pose& estimate)
{
    return glm::length(estimate.t - truth.t) / glm::length(truth.t);
}

void expectExactRecovery(const CameraIntrinsics& k)
{
    double worstRotation = 0.0, worstTranslation = 0.0;
    const std::vector<PoseCase> cases = poseGrid(k, {0.3, 0.8, 1.5, 3.0}, {0.0, 20.0, 45.0, 70.0});
    EXPECT_GE(cases.size(), 56u); // of 64
    for (const PoseCase& c : cases) {
        SCOPED_TRACE(testing::Message() << "d " << c.distance << " tilt " << c.tiltDeg << " spin " << c.spinDeg);
        const auto corners = projectTagCorners(c.truth, kTagSize, k);
        Pose estimate;
        double rms = -1.0;
        ASSERT_TRUE(solveTagPose(corners, kTagSize, k, estimate, rms));
        const double rotationError = rotationErrorRad(c.truth.R, estimate.R);
        const double translationError = relativeTranslationError(c.truth, estimate);
        EXPECT_LT(rotationError, 1e-6);
        EXPECT_LT(translationError, 1e-6);
        EXPECT_LT(rms, 1e-6);
        worstRotation = std::max(worstRotation, rotationError);
        worstTranslation = std::max(worstTranslation, translationError);
    }
    std::printf("exact corners, %dx%d, %zu poses: worst rotation error %.2e rad, translation %.2e relative\n", k.width,
                k.height, cases.size(), worstRotation, worstTranslation);
}

TEST(TagPose, ExactCornersGiveTheExactPoseIdealCamera)
{
    expectExactRecovery(defaultIntrinsics(1280, 720));
}

TEST(TagPose, ExactCornersGiveTheExactPoseDistortedCamera)
{
    expectExactRecovery(distortedCamera());
}

struct NoiseStats {
    double worstRotationDeg = 0.0;
    double worstTranslation = 0.0; // relative to the distance
    int failures = 0;
};

// Solves every case `trials` times with 0.2 px Gaussian noise on each corner coordinate.
NoiseStats solveWithNoise(const std::vector<PoseCase>& cases, const CameraIntrinsics& k, int trials, uint32_t seed)
{
    std::mt19937 rng(seed);
    std::normal_distribution<double> noise(0.0, 0.2);
    NoiseStats stats;
    for (const PoseCase& c : cases) {
        const auto exact = projectTagCorners(c.truth, kTagSize, k);

        for (int trial = 0; trial < trials; ++trial) {
            auto corners = exact;
            for (glm::dvec2& p : corners)
                p += glm::dvec2(noise(rng), noise(rng));
            Pose estimate;
            double rms = 0.0;
            if (!solveTagPose(corners, kTagSize, k, estimate, rms)) {
                ++stats.failures;
                continue;
            }
            stats.worstRotationDeg = std::max(stats.worstRotationDeg, degrees(rotationErrorRad(c.truth.R, estimate.R)));
            stats.worstTranslation = std::max(stats.worstTranslation, relativeTranslationError(c.truth, estimate));
        }
    }
    return stats;
}

// A tilted tag (30-70 degrees) that is large enough in the image (here >= 45 px a side)
// constrains its orientation well: the noisy pose stays within 1.5 degrees and 1 %.
TEST(TagPose, NoisyCornersWellConditioned)
{
    const struct {
        CameraIntrinsics k;
        std::initializer_list<double> distances;
    } setups[] = {{defaultIntrinsics(1280, 720), {0.3, 0.8, 1.2}}, {distortedCamera(), {0.3, 0.8}}};
    uint32_t seed = 1;
    for (const auto& setup : setups) {
        const NoiseStats stats =
            solveWithNoise(poseGrid(setup.k, setup.distances, {30.0, 45.0, 70.0}), setup.k, 50, seed++);
        std::printf("0.2 px noise, %dx%d, tilts 30-70 deg: worst rotation %.3f deg, translation %.3f %%\n",
                    setup.k.width, setup.k.height, stats.worstRotationDeg, 100.0 * stats.worstTranslation);
        EXPECT_EQ(stats.failures, 0);
        EXPECT_LT(stats.worstRotationDeg, 1.5);
        EXPECT_LT(stats.worstTranslation, 0.01);
    }
}

// Facing the camera squarely or far away, a square's orientation is weakly determined (the
// two IPPE solutions nearly tie, and noise picks either), but its position is not: check
// the translation only, up to 3 m.
TEST(TagPose, NoisyCornersWeakGeometryStillLocateTheTag)
{
    const CameraIntrinsics k = defaultIntrinsics(1280, 720);
    const NoiseStats frontal = solveWithNoise(poseGrid(k, {0.3, 0.8, 1.5, 3.0}, {0.0}), k, 50, 7);
    const NoiseStats far = solveWithNoise(poseGrid(k, {3.0}, {20.0, 45.0, 70.0}), k, 50, 8);
    std::printf("0.2 px noise, 1280x720: frontal 0.3-3 m worst rotation %.2f deg, translation %.3f %%; "
                "3 m tilted: worst rotation %.2f deg, translation %.3f %%\n",
                frontal.worstRotationDeg, 100.0 * frontal.worstTranslation, far.worstRotationDeg,
                100.0 * far.worstTranslation);
    EXPECT_EQ(frontal.failures, 0);
    EXPECT_EQ(far.failures, 0);
    EXPECT_LT(frontal.worstTranslation, 0.02);
    EXPECT_LT(far.worstTranslation, 0.02);
}

// core/pose.h: marker x right and y up as the tag is seen upright, z towards the viewer;
// the AprilTag order p0..p3 is (-,-), (+,-), (+,+), (-,+). So a tag facing the camera with
// its +y pointing up in the image has p0 bottom-left, p1 bottom-right, p2 top-right and p3
// top-left (image y grows downwards), and the solver must return exactly that pose.
TEST(TagPose, CornerOrderConvention)
{
    const CameraIntrinsics k = defaultIntrinsics(1280, 720);
    const Pose upright = tagPose(0.0, 0.0, 0.0, {0.0, 0.0, 1.0});
    // Marker +y maps to camera -y: up in the image.
    EXPECT_EQ(upright.R * glm::dvec3(0, 1, 0), glm::dvec3(0, -1, 0));
    const auto p = projectTagCorners(upright, kTagSize, k);
    EXPECT_LT(p[0].x, k.cx); // bottom-left
    EXPECT_GT(p[0].y, k.cy);
    EXPECT_GT(p[1].x, k.cx); // bottom-right
    EXPECT_GT(p[1].y, k.cy);
    EXPECT_GT(p[2].x, k.cx); // top-right
    EXPECT_LT(p[2].y, k.cy);
    EXPECT_LT(p[3].x, k.cx); // top-left
    EXPECT_LT(p[3].y, k.cy);

    Pose estimate;
    double rms = 0.0;
    ASSERT_TRUE(solveTagPose(p, kTagSize, k, estimate, rms));
    EXPECT_LT(rotationErrorRad(estimate.R, upright.R), 1e-6);
    EXPECT_NEAR(estimate.t.z, 1.0, 1e-6);
    const glm::dvec3 markerUpInCamera = estimate.R * glm::dvec3(0, 1, 0);
    EXPECT_NEAR(markerUpInCamera.y, -1.0, 1e-6);

    // The same tag turned upside down in its plane: p0 is now top-right.
    const auto turned = projectTagCorners(tagPose(radians(180.0), 0.0, 0.0, {0.0, 0.0, 1.0}), kTagSize, k);
    EXPECT_GT(turned[0].x, k.cx);
    EXPECT_LT(turned[0].y, k.cy);
    ASSERT_TRUE(solveTagPose(turned, kTagSize, k, estimate, rms));
    EXPECT_NEAR((estimate.R * glm::dvec3(0, 1, 0)).y, 1.0, 1e-6);
}

TEST(TagPose, MirroredCornerOrderIsRejected)
{
    // Clockwise corners are what a tag seen from behind would give: no printed tag can be.
    const CameraIntrinsics k = defaultIntrinsics(1280, 720);
    const auto p = projectTagCorners(tagPose(radians(20.0), radians(30.0), 0.4, {0.05, 0.02, 0.7}), kTagSize, k);
    const std::array<glm::dvec2, 4> mirrored{p[3], p[2], p[1], p[0]};
    Pose estimate;
    double rms = 0.0;
    EXPECT_FALSE(solveTagPose(mirrored, kTagSize, k, estimate, rms));
}

TEST(TagPose, TagBehindTheCameraIsRejected)
{
    // A pinhole projects points behind the camera too (x/z, y/z with z < 0). A tag behind
    // the camera that faces it images like a mirrored tag in front: no valid pose. (One that
    // faces away images exactly like a real tag in front, turned 180 degrees in its plane:
    // corners alone cannot tell these apart.)
    const CameraIntrinsics k = defaultIntrinsics(1280, 720);
    for (double spin : {0.0, 60.0, 200.0}) {
        const glm::dmat3 facingCameraFromBehind =
            test::axisAngle({0, 0, 1}, radians(spin)) * test::axisAngle({1, 0.3, 0}, radians(25.0));
        const Pose behind{facingCameraFromBehind, {0.05, -0.03, -0.8}};
        ASSERT_LT(glm::dot(behind.R * glm::dvec3(0, 0, 1), behind.t), 0.0); // faces the camera
        std::array<glm::dvec2, 4> corners;
        const auto marker = tagCornersInMarkerFrame(kTagSize);
        for (size_t i = 0; i < 4; ++i)
            corners[i] = k.project(behind.apply(marker[i]));
        Pose estimate;
        double rms = 0.0;
        EXPECT_FALSE(solveTagPose(corners, kTagSize, k, estimate, rms)) << "spin " << spin;
    }
}

TEST(TagPose, GarbageCornersAreRejected)
{
    const CameraIntrinsics k = defaultIntrinsics(1280, 720);
    const double nan = std::numeric_limits<double>::quiet_NaN();
    const std::array<glm::dvec2, 4> good{glm::dvec2{600, 400}, {700, 400}, {700, 300}, {600, 300}};
    const std::vector<std::array<glm::dvec2, 4>> garbage{
        {glm::dvec2{640, 360}, {640, 360}, {640, 360}, {640, 360}}, // one point
        {glm::dvec2{600, 360}, {650, 360}, {700, 360}, {750, 360}}, // collinear
        {glm::dvec2{600, 400}, {700, 300}, {700, 400}, {600, 300}}, // self-intersecting
        {glm::dvec2{600, 400}, {700, 400}, {nan, 300}, {600, 300}}, // not a number
    };
    Pose estimate;
    double rms = 0.0;
    ASSERT_TRUE(solveTagPose(good, kTagSize, k, estimate, rms));
    for (size_t i = 0; i < garbage.size(); ++i)
        EXPECT_FALSE(solveTagPose(garbage[i], kTagSize, k, estimate, rms)) << "case " << i;
    for (double size : {0.0, -0.16, nan, std::numeric_limits<double>::infinity()})
        EXPECT_FALSE(solveTagPose(good, size, k, estimate, rms)) << "size " << size;
}

} // namespace
} // namespace lumar
