// The tracking stage: AprilTag detection on the luma plane and per-tag pose with OpenCV's
// solvePnP(SOLVEPNP_IPPE_SQUARE). Corners are reported in OpenCV's pixel convention (pixel
// centres at integer coordinates: the library's corners minus 0.5) and in the library's
// order; see core/pose.h for the marker frame the pose refers to.
#pragma once

#include <array>
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
};

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

    [[nodiscard]] const CameraIntrinsics& intrinsics() const;

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

// Pose of a square tag from its four corners (OpenCV pixel convention, AprilTag order).
// Returns false for a degenerate or failed solution. Exposed for tests.
bool solveTagPose(const std::array<glm::dvec2, 4>& corners, double tagSize, const CameraIntrinsics& intrinsics,
                  Pose& cameraFromMarker, double& rmsErrorPx);

} // namespace lumar
