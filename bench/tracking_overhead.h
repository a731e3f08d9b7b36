// `lumar-bench-tracking --overhead`: what lumar's tracker costs around the AprilTag library's
// detection call. On the same luma planes (the benchmark's synthetic frames, rendered once
// before timing), interleaved in rounds whose order alternates, it times
//   - the library: apriltag_detector_detect with lumar's settings, plus lumar's IPPE pose of
//     each detection (the pose is counted on both sides, so that the ratio is the overhead);
//   - lumar's full-frame search: TagTracker::detect with roi off;
//   - `lumar detect` on stills: TagTracker::reset then detect per image (one tracker);
//   - the former `lumar detect`: a new TagTracker per image (on fewer frames: it is slow);
//   - lumar in video: TagTracker::detect with the default ROI search, the frames in order.
// Timings are measured and printed, never asserted (DESIGN.md §9).
#pragma once

#include <cstdint>
#include <string>

namespace lumar {

struct TrackingOverheadOptions {
    int width = 1280;
    int height = 720;
    int frames = 60; // rendered once, spread over the benchmark's conditions
    int rounds = 5;  // the medians are over these
    uint64_t seed = 1;
};

// A markdown report: per-round and median ms per frame of each, and the ratios to the
// library's call. Throws InputError for bad options.
std::string runTrackingOverhead(const TrackingOverheadOptions& options);

} // namespace lumar
