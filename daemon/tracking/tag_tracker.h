// The tracking stage: AprilTag detection on the luma plane and per-tag pose with OpenCV's
// solvePnP(SOLVEPNP_IPPE_SQUARE). Corners are reported in OpenCV's pixel convention (pixel
// centres at integer coordinates: the library's corners minus 0.5) and in the library's
// order; see core/pose.h for the marker frame the pose refers to.
#pragma once

#include <array>
#include <cstdint>
#include <map>
#include <memory>
#include <vector>

#include <glm/glm.hpp>

#include "config/config.h"
#include "core/camera_model.h"
#include "core/image.h"
#include "core/pose.h"

namespace lumar {

struct TagDetection {
    int id = -1;
    std::array<glm::dvec2, 4> corners{}; // OpenCV pixel convention, AprilTag order
    int hamming = 0;
    double decisionMargin = 0.0;
    bool hasPose = false; // false when the tag's size is unknown or PnP failed
    Pose cameraFromMarker;
    double reprojectionErrorPx = 0.0; // RMS over the four corners
    // IPPE's two solutions: reprojection RMS of the worse over the better one (>= 1, capped
    // at kMaxAmbiguityRatio). Below kAmbiguousRatio the tag's orientation is ambiguous (small
    // or facing the camera squarely) and the solution closest to the last pose was taken.
    double ambiguityRatio = 0.0;
};

// Error ratios below this leave the choice between IPPE's two solutions to the last pose.
inline constexpr double kAmbiguousRatio = 1.5;
inline constexpr double kMaxAmbiguityRatio = 1e6;

// Tag side lengths in metres by id; `fallback` (0: none) for ids not listed.
struct TagSizes {
    std::map<int, double> byId;
    double fallback = 0.0;
    [[nodiscard]] double of(int id) const
    {
        const auto it = byId.find(id);
        return it != byId.end() ? it->second : fallback;
    }
};

// A rectangle [x0, x1) x [y0, y1) of the image: a region of interest the tracker searched.
struct SearchWindow {
    int x0 = 0, y0 = 0, x1 = 0, y1 = 0;
    bool operator==(const SearchWindow&) const = default;
};

struct TagMap;       // tracking/tag_map.h
struct MapDetection; // tracking/tag_map.h

class TagTracker {
public:
    // Throws InputError for an unknown tag family or out-of-range settings.
    TagTracker(const TrackingConfig& config, const CameraIntrinsics& intrinsics, TagSizes sizes);
    ~TagTracker();
    TagTracker(TagTracker&&) noexcept;
    TagTracker& operator=(TagTracker&&) noexcept;
    TagTracker(const TagTracker&) = delete;
    TagTracker& operator=(const TagTracker&) = delete;

    // Detects tags in an 8-bit single-channel image; detections sorted by id.
    [[nodiscard]] std::vector<TagDetection> detect(const Image8& luma);

    // Multi-tag maps (tracking/tag_map.h). Their tags' sizes join the per-tag sizes, so
    // detect() gives each a pose; throws InputError for a size that contradicts a known one.
    void setMaps(std::vector<TagMap> maps);
    // The maps seen in `detections` (detect()'s result), in setMaps' order.
    [[nodiscard]] std::vector<MapDetection> detectMaps(const std::vector<TagDetection>& detections) const;

    [[nodiscard]] const CameraIntrinsics& intrinsics() const;

    // The windows around followed tags (DESIGN.md §5) whose search gave the last detect()'s
    // result; empty when that frame was searched whole (the first, a scheduled or a fallback
    // full-frame search, or roi off). What the setup view draws (app/setup_overlay.h).
    [[nodiscard]] const std::vector<SearchWindow>& searchedWindows() const;

    // How the frames were searched since construction (never reset): for benchmarks and logs.
    struct SearchCounts {
        uint64_t frames = 0;
        uint64_t windowSearches = 0; // frames whose windows' result stood
        uint64_t fullSearches = 0;   // frames searched whole (first, scheduled, or fallback)
        uint64_t fallbacks = 0;      // of those, after a window search that did not stand
        uint64_t coarseSearches = 0; // coarse searches of the whole frame (coarse_every)
        uint64_t coarseCatches = 0;  // of those, finding a tag the windows lacked (then a fallback)
    };
    [[nodiscard]] const SearchCounts& searchCounts() const;

    // Forgets every earlier frame (the followed tags, the last poses) and takes new intrinsics:
    // the next image is searched as a still. Cheaper than a new tracker, which builds the
    // family's decoding tables again. Throws InputError for invalid intrinsics.
    void reset(const CameraIntrinsics& intrinsics);

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

struct TagPoseSolution {
    Pose cameraFromMarker;
    double rmsErrorPx = 0.0;
    double ambiguityRatio = 0.0;  // see TagDetection
    bool choseByPrevious = false; // ambiguous, and the previous pose picked the other solution
};

// Pose of a square tag from its four corners (OpenCV pixel convention, AprilTag order):
// both IPPE solutions, each refined, the one with the lower reprojection error taken unless
// the ratio is below kAmbiguousRatio and `previous` (the same tag's last pose) is closer in
// rotation to the other. Returns false for a degenerate or failed solution (a tag behind
// the camera or seen from its back, a quad that is tiny or not convex, corners that do not
// reproject as a square). Exposed for tests.
bool solveTagPose(const std::array<glm::dvec2, 4>& corners, double tagSize, const CameraIntrinsics& intrinsics,
                  TagPoseSolution& out, const Pose* previous = nullptr);
bool solveTagPose(const std::array<glm::dvec2, 4>& corners, double tagSize, const CameraIntrinsics& intrinsics,
                  Pose& cameraFromMarker, double& rmsErrorPx);

} // namespace lumar
