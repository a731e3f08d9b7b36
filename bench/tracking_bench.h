// `lumar-bench-tracking`: lumar's TagTracker, the AprilTag library with its defaults and
// (where OpenCV's contrib aruco module was found at build time) OpenCV's ArUco detector with
// DICT_APRILTAG_36h11, run on the same synthetic frames with exact ground truth
// (bench/tracking_bench_scene.h) and scored side by side: recall, false positives, corner
// error, pose error and time. Results are measured here, never asserted in tests (DESIGN.md §9).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "bench/tracking_scoring.h"

namespace lumar {

struct TrackingBenchOptions {
    int width = 1280;
    int height = 720;
    int framesPerCondition = 30;
    uint64_t seed = 1;
};

// One detector on one condition (or "overall": every condition together).
struct TrackingBenchRow {
    std::string condition;
    std::string detector;
    int frames = 0;
    int visibleTags = 0;    // true tags with all four corners in the image
    int found = 0;          // of those, detected with the right id within kMatchRadiusPx
    int falsePositives = 0; // detections with a wrong id, or farther than kMatchRadiusPx from their tag
    double recall = 0.0;    // found / visibleTags; NaN without visible tags
    double falsePositivesPerFrame = 0.0;
    double cornerMeanPx = 0.0, cornerP95Px = 0.0; // over the corners of found tags; NaN if none
    double rotationMeanDeg = 0.0, rotationP95Deg = 0.0;
    double translationMeanPercent = 0.0, translationP95Percent = 0.0; // of the true distance
    double msPerFrame = 0.0;                                          // detection and pose, mean
};

struct TrackingBenchReport {
    TrackingBenchOptions options;
    std::vector<std::string> conditions; // in row order
    std::vector<std::string> detectors;  // in row order
    std::vector<TrackingBenchRow> rows;  // condition-major, "overall" last
    // Overall ms per frame of lumar over the AprilTag library's defaults (target <= 0.5).
    double lumarOverAprilTagTime = 0.0;
    std::vector<std::string> notes; // how the detectors were set up, what was skipped
};

// Throws InputError for bad options (size, frames per condition outside [1, 10000]).
TrackingBenchReport runTrackingBench(const TrackingBenchOptions& options);

// The report as one markdown table plus the time ratio and notes, and as one JSON object.
std::string trackingBenchMarkdown(const TrackingBenchReport& report);
std::string trackingBenchJson(const TrackingBenchReport& report);

} // namespace lumar
