// The fake camera: deterministic frames, ground truth that matches the pixels, tags always
// in view, and a noise model with the configured statistics.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <string>

#include <gtest/gtest.h>

#include "capture/fake_camera.h"
#include "core/error.h"
#include "output/frame_writer.h"

namespace lumar {
namespace {

constexpr double kPi = 3.14159265358979323846;

CameraConfig smallConfig(uint64_t seed = 1)
{
    CameraConfig config;
    config.width = 320;
    config.height = 180;
    config.seed = seed;
    return config;
}

CameraConfig fourTagConfig()
{
    CameraConfig config;
    config.fakeTags = {FakeTagConfig{3, 0.12, {-0.12, -0.09}}, FakeTagConfig{5, 0.12, {0.12, -0.09}},
                       FakeTagConfig{9, 0.10, {-0.12, 0.1}}, FakeTagConfig{14, 0.10, {0.12, 0.1}}};
    return config;
}

glm::dvec2 projectMarkerPoint(const FakeCamera& camera, const TagGroundTruth& truth, glm::dvec2 markerPoint)
{
    return camera.intrinsics().project(truth.cameraFromMarker.apply(glm::dvec3(markerPoint, 0.0)));
}

int lumaAt(const Frame& frame, glm::dvec2 pixel)
{
    const int x = int(std::lround(pixel.x));
    const int y = int(std::lround(pixel.y));
    EXPECT_TRUE(x >= 0 && y >= 0 && x < frame.luma.width && y < frame.luma.height) << x << "," << y;
    return *frame.luma.at(std::clamp(x, 0, frame.luma.width - 1), std::clamp(y, 0, frame.luma.height - 1));
}

Image8 shippedTag(int id)
{
    char name[64];
    std::snprintf(name, sizeof name, "tag36_11_%05d.png", id);
    return readImage(std::filesystem::path(LUMAR_TEST_DATA_DIR) / "apriltag" / "tag36h11" / name, 1);
}

TEST(FakeCamera, SameSeedGivesIdenticalFrames)
{
    const FakeCamera a(smallConfig(7));
    const FakeCamera b(smallConfig(7));
    Frame fa;
    Frame fb;
    for (uint64_t k : {0u, 13u, 250u}) {
        a.render(k, fa);
        b.render(k, fb);
        EXPECT_EQ(fa.rgb.data, fb.rgb.data) << "frame " << k;
        EXPECT_EQ(fa.luma.data, fb.luma.data) << "frame " << k;
    }
}

TEST(FakeCamera, DifferentSeedGivesDifferentFrames)
{
    const FakeCamera a(smallConfig(1));
    const FakeCamera b(smallConfig(2));
    Frame fa;
    Frame fb;
    a.render(0, fa);
    b.render(0, fb);
    ASSERT_EQ(fa.rgb.data.size(), fb.rgb.data.size());
    size_t differing = 0;
    for (size_t i = 0; i < fa.rgb.data.size(); ++i) {
        differing += fa.rgb.data[i] != fb.rgb.data[i];
    }
    // Noise of sigma 2 alone changes most samples.
    EXPECT_GT(differing, fa.rgb.data.size() / 2);
}

TEST(FakeCamera, RenderingFrameKDirectlyEqualsTheKthFrameOfTheStream)
{
    FakeCamera stream(smallConfig());
    const FakeCamera direct(smallConfig());
    Frame expected5;
    direct.render(5, expected5); // rendered out of order on purpose
    Frame expected2;
    direct.render(2, expected2);
    Frame frame;
    for (uint64_t k = 0; k <= 5; ++k) {
        ASSERT_TRUE(stream.next(frame));
        EXPECT_EQ(frame.sequence, k);
        EXPECT_EQ(frame.timestampNs, int64_t(std::llround(double(k) * 1e9 / 30.0)));
        if (k == 2) {
            EXPECT_EQ(frame.rgb.data, expected2.rgb.data);
        }
    }
    EXPECT_EQ(frame.rgb.data, expected5.rgb.data);
    EXPECT_EQ(frame.luma.data, expected5.luma.data);
}

TEST(FakeCamera, ReportsItsFormatAndIdealIntrinsics)
{
    const FakeCamera camera(smallConfig());
    EXPECT_EQ(camera.width(), 320);
    EXPECT_EQ(camera.height(), 180);
    EXPECT_DOUBLE_EQ(camera.fps(), 30.0);
    const CameraIntrinsics expected = defaultIntrinsics(320, 180);
    EXPECT_DOUBLE_EQ(camera.intrinsics().fx, expected.fx);
    EXPECT_DOUBLE_EQ(camera.intrinsics().cx, 159.5);
    EXPECT_DOUBLE_EQ(camera.intrinsics().cy, 89.5);
    Frame frame;
    camera.render(0, frame);
    EXPECT_EQ(frame.rgb.width, 320);
    EXPECT_EQ(frame.rgb.height, 180);
    EXPECT_EQ(frame.rgb.channels, 3);
    EXPECT_EQ(frame.luma.channels, 1);
}

TEST(FakeCamera, LumaIsBt601OfTheColour)
{
    const FakeCamera camera(smallConfig());
    Frame frame;
    camera.render(17, frame);
    for (int y = 0; y < frame.rgb.height; ++y) {
        for (int x = 0; x < frame.rgb.width; ++x) {
            const uint8_t* p = frame.rgb.at(x, y);
            const double expected = 0.299 * p[0] + 0.587 * p[1] + 0.114 * p[2];
            ASSERT_LE(std::abs(*frame.luma.at(x, y) - expected), 0.5 + 1e-9) << x << "," << y;
        }
    }
}

TEST(FakeCamera, NoiseHasTheConfiguredSigmaAndNoBias)
{
    CameraConfig clean = smallConfig(3);
    clean.noiseSigma = 0.0;
    CameraConfig noisy = smallConfig(3);
    noisy.noiseSigma = 2.0;
    Frame a;
    Frame b;
    FakeCamera(clean).render(40, a);
    FakeCamera(noisy).render(40, b);
    double sum = 0.0;
    double sumSquares = 0.0;
    const size_t n = a.rgb.data.size();
    for (size_t i = 0; i < n; ++i) {
        const double d = double(b.rgb.data[i]) - double(a.rgb.data[i]);
        sum += d;
        sumSquares += d * d;
    }
    const double mean = sum / double(n);
    const double sigma = std::sqrt(sumSquares / double(n) - mean * mean);
    // The clean frame rounds means of 4 rays (quarter values) half up: 0, −¼, +½, +¼ with
    // equal odds, which biases it by +1/8 and adds about 0.08 to the variance; rounding the
    // noisy frame adds 1/12. So the difference has mean −1/8 and sigma sqrt(4.16) = 2.04.
    EXPECT_NEAR(mean, -0.125, 0.04);
    EXPECT_NEAR(sigma, std::sqrt(4.0 + 0.078 + 1.0 / 12.0), 0.05);
}

TEST(FakeCamera, TrajectoryStaysInItsEnvelopeAndRepeatsEvery12Seconds)
{
    const FakeCamera camera(CameraConfig{});
    for (uint64_t k = 0; k < 360; k += 3) {
        const Pose cameraFromWorld = camera.cameraFromWorld(k);
        const glm::dvec3 eye = cameraFromWorld.inverse().t;
        const double distance = glm::length(eye); // the only tag sits at the origin
        const double elevation = std::asin(eye.z / distance) * 180.0 / kPi;
        EXPECT_GE(distance, 0.5 - 1e-9) << "frame " << k;
        EXPECT_LE(distance, 0.8 + 1e-9) << "frame " << k;
        EXPECT_GE(elevation, 40.0 - 1e-9) << "frame " << k;
        EXPECT_LE(elevation, 65.0 + 1e-9) << "frame " << k;
        // Rotation stays orthonormal.
        const glm::dmat3 shouldBeIdentity = cameraFromWorld.R * glm::transpose(cameraFromWorld.R);
        for (int i = 0; i < 3; ++i) {
            for (int j = 0; j < 3; ++j) {
                EXPECT_NEAR(shouldBeIdentity[i][j], i == j ? 1.0 : 0.0, 1e-12);
            }
        }
    }
    const Pose first = camera.cameraFromWorld(0);
    const Pose afterPeriod = camera.cameraFromWorld(360); // 12 s at 30 fps
    EXPECT_NEAR(glm::length(first.t - afterPeriod.t), 0.0, 1e-9);
}

// Every tag corner stays at least 20 px inside the image for the first 12 s, and the
// default tag stays large enough to track (at least 120 px across).
void expectTagsInView(const CameraConfig& config, double minimumWidth)
{
    const FakeCamera camera(config);
    const double margin = 20.0;
    for (uint64_t k = 0; k < 360; k += 5) {
        for (const TagGroundTruth& truth : camera.groundTruth(k)) {
            double minX = 1e9;
            double maxX = -1e9;
            for (const glm::dvec3& corner : tagCornersInMarkerFrame(truth.size)) {
                const glm::dvec3 p = truth.cameraFromMarker.apply(corner);
                ASSERT_GT(p.z, 0.0);
                const glm::dvec2 px = camera.intrinsics().project(p);
                EXPECT_GE(px.x, margin) << "frame " << k << " tag " << truth.id;
                EXPECT_GE(px.y, margin) << "frame " << k << " tag " << truth.id;
                EXPECT_LE(px.x, config.width - 1 - margin) << "frame " << k << " tag " << truth.id;
                EXPECT_LE(px.y, config.height - 1 - margin) << "frame " << k << " tag " << truth.id;
                minX = std::min(minX, px.x);
                maxX = std::max(maxX, px.x);
            }
            EXPECT_GE(maxX - minX, minimumWidth) << "frame " << k << " tag " << truth.id;
        }
    }
}

TEST(FakeCamera, DefaultTagStaysInViewAndLarge)
{
    expectTagsInView(CameraConfig{}, 120.0);
}

TEST(FakeCamera, FourTagLayoutStaysInView)
{
    expectTagsInView(fourTagConfig(), 40.0);
}

// The pixels agree with groundTruth(): just inside each corner is the black border, just
// outside is the white frame, and every cell centre shows the official tag image's colour.
void expectPixelsMatchGroundTruth(const CameraConfig& config)
{
    const FakeCamera camera(config);
    Frame frame;
    for (uint64_t k = 0; k < 360; k += 40) {
        camera.render(k, frame);
        for (const TagGroundTruth& truth : camera.groundTruth(k)) {
            SCOPED_TRACE("frame " + std::to_string(k) + " tag " + std::to_string(truth.id));
            const double cell = truth.size / 8.0;
            const double half = truth.size / 2.0;
            for (const glm::dvec3& corner : tagCornersInMarkerFrame(truth.size)) {
                const glm::dvec2 direction(corner.x > 0 ? 1.0 : -1.0, corner.y > 0 ? 1.0 : -1.0);
                const int inside = lumaAt(frame, projectMarkerPoint(camera, truth, direction * (half - 0.4 * cell)));
                const int outside = lumaAt(frame, projectMarkerPoint(camera, truth, direction * (half + 0.5 * cell)));
                EXPECT_LT(inside, 70);
                EXPECT_GT(outside, 190); // brighter than any wood
            }
            const Image8 reference = shippedTag(truth.id);
            for (int row = 0; row < 10; ++row) {
                for (int col = 0; col < 10; ++col) {
                    // Column 0 along the tag's −x edge, row 0 along its +y edge.
                    const glm::dvec2 centre((col - 4.5) * cell, (4.5 - row) * cell);
                    const int luma = lumaAt(frame, projectMarkerPoint(camera, truth, centre));
                    if (*reference.at(col, row) > 127) {
                        EXPECT_GT(luma, 180) << "cell " << row << "," << col;
                    } else {
                        EXPECT_LT(luma, 70) << "cell " << row << "," << col;
                    }
                }
            }
        }
    }
}

TEST(FakeCamera, PixelsMatchGroundTruthForTheDefaultTag)
{
    expectPixelsMatchGroundTruth(CameraConfig{});
}

TEST(FakeCamera, PixelsMatchGroundTruthForFourTags)
{
    expectPixelsMatchGroundTruth(fourTagConfig());
}

TEST(FakeCamera, GroundTruthPlacesEachMarkerAtItsTagCentre)
{
    const CameraConfig config = fourTagConfig();
    const FakeCamera camera(config);
    const Pose worldToCamera = camera.cameraFromWorld(77);
    const std::vector<TagGroundTruth> truths = camera.groundTruth(77);
    ASSERT_EQ(truths.size(), config.fakeTags.size());
    for (size_t i = 0; i < truths.size(); ++i) {
        EXPECT_EQ(truths[i].id, config.fakeTags[i].id);
        EXPECT_DOUBLE_EQ(truths[i].size, config.fakeTags[i].size);
        // The marker origin is the tag centre on the table; its axes are the world's.
        const glm::dvec3 centre = worldToCamera.apply(glm::dvec3(config.fakeTags[i].position, 0.0));
        EXPECT_NEAR(glm::length(truths[i].cameraFromMarker.t - centre), 0.0, 1e-12);
        const glm::dvec3 xAxis = truths[i].cameraFromMarker.R * glm::dvec3(1, 0, 0);
        EXPECT_NEAR(glm::length(xAxis - worldToCamera.R * glm::dvec3(1, 0, 0)), 0.0, 1e-12);
    }
}

TEST(FakeCamera, RejectsInvalidScenes)
{
    const auto expectError = [](CameraConfig config, const std::string& fragment) {
        try {
            FakeCamera camera(config);
            ADD_FAILURE() << "no error for " << fragment;
        } catch (const InputError& e) {
            const std::string message = e.what();
            EXPECT_NE(message.find("camera.fake_tags"), std::string::npos) << message;
            EXPECT_NE(message.find(fragment), std::string::npos) << message;
        }
    };
    CameraConfig none;
    none.fakeTags.clear();
    expectError(none, "no tags");
    CameraConfig duplicate;
    duplicate.fakeTags = {FakeTagConfig{4, 0.1, {0, 0}}, FakeTagConfig{4, 0.1, {0.3, 0}}};
    expectError(duplicate, "duplicate id 4");
    CameraConfig noCode;
    noCode.fakeTags = {FakeTagConfig{587, 0.1, {0, 0}}};
    expectError(noCode, "587");
    CameraConfig negativeId;
    negativeId.fakeTags = {FakeTagConfig{-1, 0.1, {0, 0}}};
    expectError(negativeId, "-1");
    CameraConfig zeroSize;
    zeroSize.fakeTags = {FakeTagConfig{1, 0.0, {0, 0}}};
    expectError(zeroSize, "size");
    CameraConfig negativeSize;
    negativeSize.fakeTags = {FakeTagConfig{1, -0.2, {0, 0}}};
    expectError(negativeSize, "size");

    CameraConfig farAway;
    farAway.fakeTags = {FakeTagConfig{1, 0.1, {25.0, 0}}};
    expectError(farAway, "position");

    CameraConfig badFps;
    badFps.fps = 0.0;
    EXPECT_THROW(FakeCamera{badFps}, InputError);
    CameraConfig badSize;
    badSize.width = 0;
    EXPECT_THROW(FakeCamera{badSize}, InputError);
}

// Not a pass/fail check (timings depend on the machine): prints the 720p render time.
TEST(FakeCamera, Reports720pRenderTime)
{
    const FakeCamera camera(CameraConfig{});
    Frame frame;
    camera.render(0, frame); // first touch of the buffers
    const int frames = 10;
    const auto start = std::chrono::steady_clock::now();
    for (int k = 1; k <= frames; ++k) {
        camera.render(uint64_t(k * 7), frame);
    }
    const double ms =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count() / frames;
    RecordProperty("ms_per_1280x720_frame", std::to_string(ms));
    std::printf("fake camera: %.2f ms per 1280x720 frame\n", ms);
}

} // namespace
} // namespace lumar
