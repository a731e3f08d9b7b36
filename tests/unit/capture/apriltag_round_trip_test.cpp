// The real detector on the fake camera's frames: it must find every tag with the right id
// and put its corners where the ground truth projects them.
#include <algorithm>
#include <cstdio>
#include <memory>
#include <string>

#include <apriltag/apriltag.h>
#include <apriltag/common/zarray.h>
#include <apriltag/tag36h11.h>
#include <gtest/gtest.h>

#include "capture/fake_camera.h"
#include "config/config.h"

namespace lumar {
namespace {

struct DetectorDeleter {
    void operator()(apriltag_detector_t* d) const { apriltag_detector_destroy(d); }
};
struct FamilyDeleter {
    void operator()(apriltag_family_t* f) const { tag36h11_destroy(f); }
};
struct DetectionsDeleter {
    void operator()(zarray_t* z) const { apriltag_detections_destroy(z); }
};

class Detector {
public:
    Detector() : family_(tag36h11_create()), detector_(apriltag_detector_create())
    {
        apriltag_detector_add_family(detector_.get(), family_.get());
        detector_->quad_decimate = 1.0f; // full resolution: this test is about accuracy
        detector_->quad_sigma = 0.0f;
        detector_->refine_edges = true;
        detector_->nthreads = 2;
    }

    std::unique_ptr<zarray_t, DetectionsDeleter> detect(Image8& luma)
    {
        image_u8_t image{luma.width, luma.height, luma.width, luma.data.data()};
        return std::unique_ptr<zarray_t, DetectionsDeleter>(apriltag_detector_detect(detector_.get(), &image));
    }

private:
    std::unique_ptr<apriltag_family_t, FamilyDeleter> family_;
    std::unique_ptr<apriltag_detector_t, DetectorDeleter> detector_;
};

// Returns the largest corner error in pixels over the frames.
double checkRoundTrip(const CameraConfig& config, std::initializer_list<uint64_t> frames)
{
    const FakeCamera camera(config);
    Detector detector;
    Frame frame;
    double worst = 0.0;
    double sum = 0.0;
    int count = 0;
    for (const uint64_t k : frames) {
        SCOPED_TRACE("frame " + std::to_string(k));
        camera.render(k, frame);
        const auto detections = detector.detect(frame.luma);
        const std::vector<TagGroundTruth> truths = camera.groundTruth(k);
        EXPECT_EQ(zarray_size(detections.get()), int(truths.size()));
        for (int i = 0; i < zarray_size(detections.get()); ++i) {
            apriltag_detection_t* detection = nullptr;
            zarray_get(detections.get(), i, &detection);
            const auto truth = std::find_if(truths.begin(), truths.end(),
                                            [&](const TagGroundTruth& t) { return t.id == detection->id; });
            if (truth == truths.end()) {
                ADD_FAILURE() << "unexpected id " << detection->id;
                continue;
            }
            EXPECT_EQ(detection->hamming, 0);
            const auto corners = tagCornersInMarkerFrame(truth->size);
            for (int c = 0; c < 4; ++c) {
                const glm::dvec2 expected =
                    camera.intrinsics().project(truth->cameraFromMarker.apply(corners[size_t(c)]));
                // The library's pixel (0,0) covers [0,1]², ours [-0.5,0.5]².
                const glm::dvec2 detected(detection->p[c][0] - 0.5, detection->p[c][1] - 0.5);
                const double error = glm::length(detected - expected);
                EXPECT_LT(error, 0.5) << "tag " << truth->id << " corner " << c;
                worst = std::max(worst, error);
                sum += error;
                ++count;
            }
        }
    }
    if (count > 0) {
        std::printf("apriltag corner error: mean %.3f px, max %.3f px over %d corners\n", sum / count, worst, count);
    }
    return worst;
}

TEST(FakeCameraAprilTag, DetectsTheDefaultTagWithSubPixelCorners)
{
    const double worst = checkRoundTrip(CameraConfig{}, {0, 45, 90, 135, 180, 225, 270, 315});
    RecordProperty("max_corner_error_px", std::to_string(worst));
}

TEST(FakeCameraAprilTag, DetectsFourTagsWithSubPixelCorners)
{
    CameraConfig config;
    config.fakeTags = {FakeTagConfig{3, 0.12, {-0.12, -0.09}}, FakeTagConfig{5, 0.12, {0.12, -0.09}},
                       FakeTagConfig{9, 0.10, {-0.12, 0.1}}, FakeTagConfig{14, 0.10, {0.12, 0.1}}};
    const double worst = checkRoundTrip(config, {0, 100, 200, 300});
    RecordProperty("max_corner_error_px", std::to_string(worst));
}

// The shipped scene: the table in the sunset the objects are lit by, a box beside the tag.
TEST(FakeCameraAprilTag, DetectsTheDefaultTagInTheShippedWorld)
{
    const CameraConfig config = defaultConfig().camera;
    ASSERT_FALSE(config.fakeEnvironment.empty());
    ASSERT_FALSE(config.fakeObjects.empty());
    const double worst = checkRoundTrip(config, {0, 45, 90, 135, 180, 225, 270, 315});
    RecordProperty("max_corner_error_px", std::to_string(worst));
}

} // namespace
} // namespace lumar
