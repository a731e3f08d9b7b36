// `lumar-bench-tracking --sequences`: the tracker scored whole on temporal sequences (issue
// 19), not on frames taken one by one. Generated with exact ground truth by the benchmark's
// scene (bench/tracking_bench_scene.h), deterministic for a seed:
//   blink_low_light   two tags in low light, one hidden on single frames at every phase of the
//                     full-frame schedule;
//   occlusion_ends    two tags, one covered for 1 to 13 frames, the covers ending at
//                     different phases of the schedule;
//   leave_reenter     a pan that takes one of two tags out of the view and back;
//   fast_pan          one tag, still, then panned across the view at 0.75 m/s with motion
//                     blur along the pan, then still;
//   board_4           a 2x2 board of tags solved as a [[maps]] board, the camera orbiting and
//                     then still.
// And real photos: the AprilTag library's three test photos (../shared/data/apriltag/real,
// its MANIFEST.md: NASA rovers, 10 to 25 small oblique tags each, the corners the library
// recorded as ground truth), each a still sequence of frames with fresh sensor noise (a
// camera held still): recall against the recorded tags, corner error and corner jitter.
// Each is run frame by frame by lumar's tracker with its pose filter (TrackedPoses, as the
// renderer draws; with threads 1 and 2, or the configurations given) and by the AprilTag library's defaults (its raw
// poses; the board solved from its tags by lumar's map solver), and scored: recall,
// re-acquisition delay (frames from a tag's first visible frame after being hidden or out of
// view to the frame it is found), jitter (standard deviation of the pose error while the
// camera is still, and of the found corners), lag (pose error along the motion in the pan),
// and wall and CPU ms per frame (CPU: the whole process, a helper thread's time included).
// Measured and printed, never asserted in tests (DESIGN.md §9).
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "config/config.h"

namespace lumar {

// One configuration of lumar's tracker to compare.
struct LumarVariant {
    std::string name;
    TrackingConfig config;
};

// "NAME" or "NAME:key=value,key=value" with keys of lumar.toml's [tracking] table over its
// defaults (threads 1 unless given), e.g. "coarse:coarse_every=1". Throws InputError.
LumarVariant parseLumarVariant(const std::string& text);

struct TrackingSequencesOptions {
    int width = 1280;
    int height = 720;
    uint64_t seed = 1;
    int rounds = 1; // every detector over every sequence this often, order alternating; ms: median
    // Empty: "lumar" ([tracking] defaults, threads 1) and "lumar_2threads" (threads 2).
    std::vector<LumarVariant> lumar;
    // Holds apriltag/real/ (the library's photos); empty or without them: no photo rows.
    std::filesystem::path dataDir;
    int photoFrames = 20; // frames per photo sequence
};

struct TrackingSequenceRow {
    std::string sequence;
    std::string detector;
    int frames = 0;
    int visibleTags = 0; // tag-frames with the tag visible (in view, not covered)
    int found = 0;
    double recall = 0.0;                // NaN without visible tags
    int reacquisitions = 0;             // times a tag became visible again after >= 1 frame hidden or away
    double reacquireMeanFrames = 0;     // frames from visible again to found (0: at once); NaN if none
    int reacquireMaxFrames = 0;         // the longest (the sequence's end counts for one never found)
    double jitterMm = 0, jitterDeg = 0; // std of the drawn pose's error while still; NaN if none
    double lagMm = 0, lagMs = 0;        // mean error along the motion while panning; NaN if none
    double cornerMeanPx = 0.0;          // corner error of the found tags; NaN if none
    double cornerJitterPx = 0.0;        // RMS of the found corners about their mean while still; NaN if none
    double msPerFrame = 0.0;            // detection, pose, map and filter; median over rounds
    double cpuMsPerFrame = 0.0;         // the same in CPU time of the process; median over rounds
};

struct TrackingSequencesReport {
    TrackingSequencesOptions options;
    std::vector<TrackingSequenceRow> rows; // sequence-major
    std::vector<std::string> notes;
};

// Throws InputError for bad options.
TrackingSequencesReport runTrackingSequences(const TrackingSequencesOptions& options);
std::string trackingSequencesMarkdown(const TrackingSequencesReport& report);
std::string trackingSequencesJson(const TrackingSequencesReport& report);

} // namespace lumar
