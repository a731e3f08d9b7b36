// Multi-tag maps (DESIGN.md §5): a board or a set of tags with a known layout, solved for
// one pose from every detected tag's corners at once. More corners, spread wider than one
// tag's, pin the orientation down far better than a single tag and remove IPPE's two-fold
// ambiguity; the map is still found while some of its tags are hidden.
#pragma once

#include <array>
#include <string>
#include <vector>

#include "config/config.h"
#include "core/camera_model.h"
#include "core/pose.h"
#include "tracking/tag_tracker.h"

namespace lumar {

struct TagMapTag {
    int id = 0;
    double size = 0.0; // metres
    Pose mapFromTag;   // the tag's frame (core/pose.h) in the map frame
};

struct TagMap {
    std::string name;
    std::vector<TagMapTag> tags;
};

// The tags' poses from the config: rotation R = Rz * Ry * Rx (degrees), then `position`.
TagMap makeTagMap(const MapConfig& config);

struct MapDetection {
    int index = -1; // the map's index in the tracker's list (the config's order)
    std::string name;
    Pose cameraFromMap;
    int tagsUsed = 0;
    std::vector<int> tagIds;          // the tags used, by id
    double reprojectionErrorPx = 0.0; // RMS over all their corners
};

// Solves `map`'s pose from those of its tags detected once and with a per-tag pose: the
// per-tag pose that, carried into the map frame, reprojects all the corners best starts
// cv::solvePnP(SOLVEPNP_ITERATIVE) over all of them (through the lens distortion, as the
// per-tag solver does). False when no tag of the map is usable or the result is implausible
// (not finite, a corner behind the camera, or an RMS error above 4 px).
bool solveMapPose(const TagMap& map, const std::vector<TagDetection>& detections, const CameraIntrinsics& intrinsics,
                  MapDetection& out);

// Where `tag` of a map seen with `cameraFromMap` appears: its corners (OpenCV pixel convention,
// AprilTag order, through the lens distortion). False when a corner is behind the camera or
// the tag shows the camera its back.
bool projectMapTag(const TagMapTag& tag, const Pose& cameraFromMap, const CameraIntrinsics& intrinsics,
                   std::array<glm::dvec2, 4>& corners);

} // namespace lumar
