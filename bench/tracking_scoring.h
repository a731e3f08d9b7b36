// What `lumar-bench-tracking`'s stills (tracking_bench.cpp) and sequences
// (tracking_sequences.cpp) score with alike: one rule matching detections to the true tags,
// one set of statistics, one markdown table writer, one wrapper of the AprilTag library run
// with its defaults, and the clocks (wall and process CPU time) the detectors are timed with.
#pragma once

#include <array>
#include <memory>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "bench/tracking_bench_scene.h"
#include "core/camera_model.h"
#include "core/image.h"
#include "tracking/tag_tracker.h"

namespace lumar {

// A detection within this distance (centre to centre) of the true tag with its id is found.
inline constexpr double kMatchRadiusPx = 10.0;

glm::dvec2 centreOf(const std::array<glm::dvec2, 4>& corners);

// One frame's detections matched to its true tags.
struct FrameMatch {
    std::vector<int> detectionOf; // per true tag: the index of its detection, -1 if none
    int falsePositives = 0;       // detections of no tag: a wrong id, a wrong place, a second copy
};

// Each detection, in order, goes to the nearest true tag with its id within kMatchRadiusPx
// that no detection took yet (ids may repeat, as in the library's photos).
FrameMatch matchDetections(const std::vector<BenchTagTruth>& truths, const std::vector<TagDetection>& found);

// The angle of the rotation taking `a` to `b`, in degrees, exact for small angles too.
double rotationErrorDeg(const glm::dmat3& a, const glm::dmat3& b);
// The rotation taking `truth` to `measured` as a rotation vector (radians).
glm::dvec3 rotationVector(const glm::dmat3& truth, const glm::dmat3& measured);

// NaN for an empty input.
double mean(const std::vector<double>& v);
double median(std::vector<double> v);
double percentile95(std::vector<double> v);
// The samples' standard deviation about their mean (length of the 3-vector); NaN below 2.
double standardDeviation(const std::vector<glm::dvec3>& samples);

// `v` with `decimals` digits after the point; "–" for NaN or infinity.
std::string fixed(double v, int decimals);

// A markdown table: the first `textColumns` columns left-aligned, the others (numbers) right.
class MarkdownTable {
public:
    MarkdownTable(std::vector<std::string> header, size_t textColumns);
    void add(std::vector<std::string> cells);
    [[nodiscard]] std::string str() const;

private:
    std::vector<std::string> header_;
    size_t textColumns_;
    std::vector<std::vector<std::string>> rows_;
};

// Seconds of the monotonic clock, and of CPU time used by the whole process (every thread:
// lumar's helper thread counts).
double wallSeconds();
double processCpuSeconds();

// The AprilTag library as its users start it: tag36h11, apriltag_detector_create()'s
// defaults, 2 correctable bits, searched whole on every frame. Its corners are shifted by
// -0.5 px into OpenCV's pixel convention, as lumar's tracker does, and each detection of a
// known size gets lumar's IPPE pose (solveTagPose, without history), so that pose errors
// differ only by the corners found.
class AprilTagDefaults {
public:
    AprilTagDefaults();
    ~AprilTagDefaults();
    AprilTagDefaults(const AprilTagDefaults&) = delete;
    AprilTagDefaults& operator=(const AprilTagDefaults&) = delete;

    std::vector<TagDetection> detect(const Image8& luma, const TagSizes& sizes, const CameraIntrinsics& k);
    // The settings it runs with, for the report's notes.
    [[nodiscard]] std::string settings() const;

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

} // namespace lumar
