// The synthetic sequence of `lumar-bench-tracking`: tag36h11 markers lying on a cluttered
// plane, seen by a pinhole camera on a smooth seeded path, rendered with OpenCV (tags
// supersampled 4x4 so their edges are sub-pixel exact) and then degraded per condition
// (noise, motion blur, defocus, low light, occlusion, steep views, several tags, no tags).
// Every frame carries exact ground truth: each tag's camera_from_marker pose and corners.
//
// It renders its own frames instead of using capture/FakeCamera because the benchmark must
// choose the camera pose (views up to 75 degrees from the tag normal, views away from every
// tag), which the fake camera's fixed orbit does not allow.
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "core/camera_model.h"
#include "core/image.h"
#include "core/pose.h"

namespace lumar {

struct BenchTag {
    int id = 0;
    double size = 0.16;       // metres, black border to black border
    glm::dvec2 position{0.0}; // centre on the plane z = 0; marker frame = world frame moved there
};

// One condition of the sequence: its scene and what happens to its frames.
struct BenchCondition {
    std::string name;
    std::vector<BenchTag> tags;
    double minTiltDeg = 0.0, maxTiltDeg = 40.0;  // camera direction from the plane's normal
    double minDistance = 0.5, maxDistance = 1.6; // metres from the point looked at
    double noiseSigma = 1.5;                     // Gaussian sensor noise, code values
    double motionBlurPx = 0.0;                   // > 0: a linear blur of up to this length (at 1280 px wide)
    double defocusSigmaPx = 0.0;                 // > 0: Gaussian blur of up to this sigma (at 1280 px wide)
    bool lowLight = false;                       // dark exposure, gamma, stronger noise
    bool occlude = false;                        // a grey patch over part of the first tag
    bool lookAway = false;                       // aim far from every tag: no tag in view
    // For renderView (the temporal sequences, bench/tracking_sequences.h):
    double motionBlurAngleDeg = -1.0; // >= 0: a blur of exactly motionBlurPx along this image angle
    double exposure = 0.0;            // with lowLight: the light's scale (0: random in [0.15, 0.25])
    std::vector<int> covered{};       // ids hidden wholly under a grey patch (not visible)
};

struct BenchTagTruth {
    int id = 0;
    double size = 0.0;
    Pose cameraFromMarker;
    std::array<glm::dvec2, 4> corners{}; // OpenCV pixel convention, AprilTag order
    bool visible = false;                // all four corners inside the image, tag facing the camera
};

struct BenchFrame {
    Image8 luma;
    std::vector<BenchTagTruth> tags; // every tag of the condition, visible or not
};

class TrackingBenchScene {
public:
    // Throws InputError for a size outside [64, 8192] pixels.
    TrackingBenchScene(int width, int height, uint64_t seed);
    ~TrackingBenchScene();
    TrackingBenchScene(const TrackingBenchScene&) = delete;
    TrackingBenchScene& operator=(const TrackingBenchScene&) = delete;

    // The conditions, in report order.
    static const std::vector<BenchCondition>& conditions();

    // Renders frame `frame` of `frames` of condition `condition` (deterministic: the same
    // arguments and seed give the same image). The camera sweeps the condition's ranges once
    // over the `frames` frames, so consecutive frames move smoothly.
    void render(size_t condition, int frame, int frames, BenchFrame& out) const;

    // Renders any scene: `condition`'s tags, seen from `cameraFromWorld`, degraded as it says
    // (its occlude and lookAway are not used), the noise and random blur drawn from `noiseSeed`.
    void renderView(const BenchCondition& condition, const Pose& cameraFromWorld, uint64_t noiseSeed,
                    BenchFrame& out) const;

    [[nodiscard]] const CameraIntrinsics& intrinsics() const;

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

} // namespace lumar
