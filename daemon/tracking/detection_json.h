// The one-line JSON form of an image's detections, as `lumar detect` prints it:
// {"file":"a.png","detections":[{"id":0,"hamming":0,"margin":87.5,
//   "corners":[[x,y],[x,y],[x,y],[x,y]],"R":[[..],[..],[..]],"t":[x,y,z]}]}
// Corners in the AprilTag library's order and OpenCV's pixel convention; R row-major; R
// and t (camera_from_marker, metres) only for detections with a pose. A file name that is
// not valid UTF-8 has U+FFFD in place of what is ill-formed (core/json_output.h).
#pragma once

#include <string>
#include <vector>

#include "core/json_output.h"
#include "tracking/tag_map.h"
#include "tracking/tag_tracker.h"
#include "tracking/tracked_poses.h"

namespace lumar {

std::string detectionsToJson(const std::string& file, const std::vector<TagDetection>& detections);
// The same as an object, for callers that add fields (lumar detect's maps and filtered poses).
Json detectionsJson(const std::string& file, const std::vector<TagDetection>& detections);

// Adds "R" (rows) and "t" of a camera_from_marker pose to a detection's object, to 9
// significant digits; the frame trace (app/frame_trace.cpp) writes its poses with it too.
void addPoseJson(Json& detection, const Pose& cameraFromMarker);

// A map's measured pose: {"map":"board","tags":[0,1,2],"error_px":0.21,"R":..,"t":..}.
Json mapDetectionJson(const MapDetection& map);

// A filtered pose as drawn (TrackedPoses::Used): {"id":3,...} for a tag, {"map":"board",...}
// for a map (named from `mapNames`, the config's [[maps]] in order), then "last_seen" (the
// frame last measured in), "R" and "t".
Json trackedPoseJson(const TrackedPoses::Used& used, const std::vector<std::string>& mapNames);

} // namespace lumar
