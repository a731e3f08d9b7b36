// End to end through TagTracker::detect on a tag rendered with a known pose: checks the whole
// convention chain at once — the marker frame (the PNG's row 0 is the +y edge), the corner
// order, the half-pixel offset and the pose.
#include <cstdio>
#include <random>
#include <string>
#include <utility>

#include <gtest/gtest.h>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "core/error.h"
#include "tracking/tag_tracker.h"
#include "tracking_test_support.h"

namespace lumar {
namespace {

using test::radians;

constexpr double kTagSize = 0.16;  // the 8x8 black-bordered part, metres
constexpr int kTagCells = 10;      // the PNG: 8x8 tag plus a 1-cell white frame
constexpr int kTexelsPerCell = 16; // nearest-neighbour upscale of the PNG
constexpr int kSupersampling = 4;  // rendered at 4x and box-filtered down: smooth edges

// Renders the tag36h11 id 0 PNG seen by camera `k` with `cameraFromMarker` over a grey
// background. Pixel centres sit at integer coordinates in the texture, the high-resolution
// and the final image alike (OpenCV's convention, which warpPerspective follows).
cv::Mat renderTag(const Pose& cameraFromMarker, const CameraIntrinsics& k)
{
    const cv::Mat png =
        cv::imread(std::string(LUMAR_TEST_DATA_DIR) + "/apriltag/tag36h11/tag36_11_00000.png", cv::IMREAD_GRAYSCALE);
    EXPECT_EQ(png.cols, kTagCells);
    cv::Mat texture;
    cv::resize(png, texture, {}, kTexelsPerCell, kTexelsPerCell, cv::INTER_NEAREST);

    // Texel (u, v) -> marker (X, Y): the PNG's column c in [0, 10] cells spans X from -5/8 s
    // to +5/8 s, and row 0 is the +y edge.
    const double metresPerCell = kTagSize / 8.0;
    const double a = metresPerCell / kTexelsPerCell;
    const double b = metresPerCell * (0.5 / kTexelsPerCell - kTagCells / 2.0);
    const cv::Matx33d markerFromTexel(a, 0, b, 0, -a, -b, 0, 0, 1);
    // Marker plane (X, Y, 1) -> camera -> pixels: K [r1 r2 t].
    const glm::dmat3& R = cameraFromMarker.R;
    const glm::dvec3& t = cameraFromMarker.t;
    const cv::Matx33d planeToCamera(R[0][0], R[1][0], t.x, R[0][1], R[1][1], t.y, R[0][2], R[1][2], t.z);
    const cv::Matx33d K(k.fx, 0, k.cx, 0, k.fy, k.cy, 0, 0, 1);
    // Final pixel x -> high-resolution pixel S x + (S - 1) / 2.
    const double s = kSupersampling;
    const cv::Matx33d toHighRes(s, 0, (s - 1) / 2, 0, s, (s - 1) / 2, 0, 0, 1);
    const cv::Matx33d texelToHighRes = toHighRes * K * planeToCamera * markerFromTexel;

    cv::Mat highRes;
    cv::warpPerspective(texture, highRes, cv::Mat(texelToHighRes),
                        {k.width * kSupersampling, k.height * kSupersampling}, cv::INTER_LINEAR, cv::BORDER_CONSTANT,
                        cv::Scalar(128));
    cv::Mat image;
    cv::resize(highRes, image, {k.width, k.height}, 0, 0, cv::INTER_AREA);
    return image;
}

struct RenderCase {
    const char* name;
    Pose truth;
};

void expectDetectedAsRendered(const TrackingConfig& config)
{
    const CameraIntrinsics k = defaultIntrinsics(1280, 720);
    const RenderCase cases[] = {
        {"upright, facing the camera", test::tagPose(0.0, 0.0, 0.0, {0.0, 0.0, 0.5})},
        {"tilted 35 deg, turned 20 deg", test::tagPose(radians(20.0), radians(35.0), 0.3, {0.08, -0.04, 0.7})},
        {"tilted 55 deg, upside down", test::tagPose(radians(200.0), radians(55.0), 2.0, {-0.1, 0.05, 0.9})},
    };
    TagSizes sizes;
    sizes.byId[0] = kTagSize;
    TagTracker tracker(config, k, sizes);
    for (const RenderCase& c : cases) {
        SCOPED_TRACE(c.name);
        const auto detections = tracker.detect(test::toImage8(renderTag(c.truth, k)));
        ASSERT_EQ(detections.size(), 1u);
        const TagDetection& d = detections[0];
        EXPECT_EQ(d.id, 0);
        EXPECT_EQ(d.hamming, 0);
        const auto truthCorners = test::projectTagCorners(c.truth, kTagSize, k);
        double worstCorner = 0.0;
        glm::dvec2 meanOffset(0.0);
        for (size_t i = 0; i < 4; ++i) {
            const double error = glm::length(d.corners[i] - truthCorners[i]);
            EXPECT_LT(error, 0.5) << "corner " << i;
            worstCorner = std::max(worstCorner, error);
            meanOffset += 0.25 * (d.corners[i] - truthCorners[i]);
        }
        // Edges along the pixel grid make the library's quad up to ~0.25 px too small or
        // large (its edge points are quantised to pixel boundaries), but symmetrically; a
        // pixel-convention slip would shift all four corners by (0.5, 0.5).
        EXPECT_LT(glm::length(meanOffset), 0.15);
        ASSERT_TRUE(d.hasPose);
        const double rotationDeg = test::degrees(test::rotationErrorRad(c.truth.R, d.cameraFromMarker.R));
        const double translation = glm::length(d.cameraFromMarker.t - c.truth.t) / glm::length(c.truth.t);
        EXPECT_LT(rotationDeg, 1.0);
        EXPECT_LT(translation, 0.01);
        std::printf("rendered tag, %s, quad_decimate %g: worst corner %.3f px, mean offset %.3f px, rotation %.3f deg, "
                    "translation %.3f %%\n",
                    c.name, config.quadDecimate, worstCorner, glm::length(meanOffset), rotationDeg,
                    100.0 * translation);
    }
}

TEST(RenderedTag, DetectedWhereRenderedDefaultSettings)
{
    expectDetectedAsRendered(TrackingConfig{});
}

TEST(RenderedTag, DetectedWhereRenderedFullResolution)
{
    TrackingConfig config;
    config.quadDecimate = 1.0;
    config.refineEdges = false;
    expectDetectedAsRendered(config);
}

TEST(RenderedTag, UprightTagHasP0BottomLeftAndP3TopLeft)
{
    const CameraIntrinsics k = defaultIntrinsics(1280, 720);
    TagTracker tracker(TrackingConfig{}, k, TagSizes{});
    const auto detections = tracker.detect(test::toImage8(renderTag(test::tagPose(0, 0, 0, {0, 0, 0.6}), k)));
    ASSERT_EQ(detections.size(), 1u);
    const auto& p = detections[0].corners;
    EXPECT_LT(p[0].x, k.cx);
    EXPECT_GT(p[0].y, k.cy);
    EXPECT_GT(p[1].x, k.cx);
    EXPECT_GT(p[1].y, k.cy);
    EXPECT_GT(p[2].x, k.cx);
    EXPECT_LT(p[2].y, k.cy);
    EXPECT_LT(p[3].x, k.cx);
    EXPECT_LT(p[3].y, k.cy);
    EXPECT_FALSE(detections[0].hasPose); // no size known for the tag
}

TEST(RenderedTag, QuadSigmaBlurLeavesTheCallersImageUntouched)
{
    // With quad_decimate 1 the library blurs its input in place; the tracker must hand it a
    // copy, not the caller's const frame.
    const CameraIntrinsics k = defaultIntrinsics(1280, 720);
    TrackingConfig config;
    config.quadDecimate = 1.0;
    config.quadSigma = 0.8;
    TagTracker tracker(config, k, TagSizes{});
    const Image8 frame = test::toImage8(renderTag(test::tagPose(0.3, 0.2, 1.0, {0, 0, 0.6}), k));
    const Image8 before = frame;
    EXPECT_EQ(tracker.detect(frame).size(), 1u);
    EXPECT_EQ(frame.data, before.data);
}

TEST(TagTrackerSettings, FamiliesByName)
{
    const CameraIntrinsics k = defaultIntrinsics(64, 48);
    for (const char* family : {"tag36h11", "tag25h9", "tag16h5", "tagCircle21h7", "tagStandard41h12"}) {
        TrackingConfig config;
        config.family = family;
        EXPECT_NO_THROW(TagTracker(config, k, TagSizes{})) << family;
    }
    TrackingConfig config;
    config.family = "tag36h12";
    try {
        TagTracker tracker(config, k, TagSizes{});
        FAIL() << "expected InputError";
    } catch (const InputError& e) {
        EXPECT_STREQ(e.what(), "unknown tag family 'tag36h12'");
    }
}

TEST(TagTrackerSettings, BadSettingsAndImagesAreInputErrors)
{
    const CameraIntrinsics k = defaultIntrinsics(64, 48);
    const auto withConfig = [&](auto change) {
        TrackingConfig config;
        change(config);
        return TagTracker(config, k, TagSizes{});
    };
    EXPECT_THROW(withConfig([](TrackingConfig& c) { c.quadDecimate = 0.5; }), InputError);
    EXPECT_THROW(withConfig([](TrackingConfig& c) { c.threads = 0; }), InputError);
    EXPECT_THROW(withConfig([](TrackingConfig& c) { c.decodeSharpening = -1.0; }), InputError);
    EXPECT_THROW(withConfig([](TrackingConfig& c) { c.quadSigma = NAN; }), InputError);
    TagSizes negative;
    negative.byId[3] = -0.1;
    EXPECT_THROW(TagTracker(TrackingConfig{}, k, negative), InputError);
    EXPECT_THROW(TagTracker(TrackingConfig{}, CameraIntrinsics{}, TagSizes{}), InputError);

    TagTracker tracker(TrackingConfig{}, k, TagSizes{});
    EXPECT_THROW((void)tracker.detect(Image8(64, 48, 3)), InputError); // not luma
    EXPECT_THROW((void)tracker.detect(Image8(32, 48, 1)), InputError); // not the calibrated size
    EXPECT_TRUE(tracker.detect(Image8(64, 48, 1)).empty());            // blank frame
}

TEST(TagTrackerSettings, TinyImagesGiveNoDetections)
{
    const CameraIntrinsics k = defaultIntrinsics(4, 3);
    TagTracker tracker(TrackingConfig{}, k, TagSizes{});
    EXPECT_TRUE(tracker.detect(Image8(4, 3, 1)).empty());
}

// Also a regression test for libapriltag < 3.4.3's worker-pool race: with two threads and
// a fresh detector per image this crashed in about one run in seven here.
TEST(TagTrackerSettings, NoiseImagesOfOddSizesAreHandled)
{
    std::mt19937 rng(5);
    for (const auto& [w, h] : {std::pair{8, 8}, {9, 300}, {300, 9}, {17, 33}, {641, 479}}) {
        Image8 noise(w, h, 1);
        for (uint8_t& v : noise.data)
            v = uint8_t(rng() & 0xFF);
        for (double decimate : {1.0, 2.0, 3.0}) {
            TrackingConfig config;
            config.quadDecimate = decimate;
            TagSizes sizes;
            sizes.fallback = 0.1;
            TagTracker tracker(config, defaultIntrinsics(w, h), sizes);
            EXPECT_NO_THROW((void)tracker.detect(noise)) << w << "x" << h << " decimate " << decimate;
        }
    }
}

TEST(TagTrackerSettings, MovedTrackerStillDetects)
{
    const CameraIntrinsics k = defaultIntrinsics(1280, 720);
    TagTracker first(TrackingConfig{}, k, TagSizes{});
    TagTracker second = std::move(first);
    EXPECT_EQ(second.intrinsics().width, 1280);
    EXPECT_EQ(second.detect(test::toImage8(renderTag(test::tagPose(0, 0.4, 0, {0, 0, 0.8}), k))).size(), 1u);
}

} // namespace
} // namespace lumar

namespace lumar {
namespace {

// Region-of-interest search: on a moving tag it finds the same tag, with the same corners
// (the window is aligned to the decimation grid and threshold tiles; measured 0.002 px) as a
// full-frame search; when the tag jumps out of the window it falls back to the full frame.
TEST(RegionOfInterest, FollowsAMovingTagLikeAFullFrameSearch)
{
    const CameraIntrinsics k = defaultIntrinsics(1280, 720);
    TagSizes sizes;
    sizes.byId[0] = kTagSize;
    TrackingConfig roiConfig;
    roiConfig.roi = true;
    roiConfig.fullFrameEvery = 100;
    TrackingConfig fullConfig = roiConfig;
    fullConfig.roi = false;
    TagTracker withRoi(roiConfig, k, sizes);
    TagTracker fullFrame(fullConfig, k, sizes);
    double worst = 0.0;
    for (int frame = 0; frame < 12; ++frame) {
        // 1 cm and 2 degrees per frame, then a jump to the other side of the image.
        const double x = frame < 10 ? -0.1 + 0.01 * frame : 0.15;
        const Pose truth = test::tagPose(radians(2.0 * frame), radians(30.0), 0.5, {x, 0.02, 0.7});
        const Image8 image = test::toImage8(renderTag(truth, k));
        const auto a = withRoi.detect(image);
        const auto b = fullFrame.detect(image);
        ASSERT_EQ(a.size(), 1u) << "frame " << frame;
        ASSERT_EQ(b.size(), 1u) << "frame " << frame;
        for (size_t i = 0; i < 4; ++i)
            worst = std::max(worst, glm::length(a[0].corners[i] - b[0].corners[i]));
        EXPECT_TRUE(a[0].hasPose);
    }
    RecordProperty("worst_corner_difference_px", std::to_string(worst));
    EXPECT_LT(worst, 0.01);
}

} // namespace
} // namespace lumar
