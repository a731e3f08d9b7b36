// The one-line JSON form of an image's detections, as `lumar detect` prints it:
// {"file":"a.png","detections":[{"id":0,"hamming":0,"margin":87.5,
//   "corners":[[x,y],[x,y],[x,y],[x,y]],"R":[[..],[..],[..]],"t":[x,y,z]}]}
// Corners in the AprilTag library's order and OpenCV's pixel convention; R row-major; R
// and t (camera_from_marker, metres) only for detections with a pose.
#pragma once

#include <string>
#include <vector>

#include "tracking/tag_tracker.h"

namespace lumar {

std::string detectionsToJson(const std::string& file, const std::vector<TagDetection>& detections);

// A JSON string literal (with the quotes) for UTF-8 text; invalid UTF-8 bytes become U+FFFD.
std::string jsonString(const std::string& text);

} // namespace lumar
