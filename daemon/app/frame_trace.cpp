#include "frame_trace.h"

#include <cerrno>
#include <cstring>
#include <string>

#include "core/error.h"
#include "tracking/detection_json.h"

namespace lumar {
namespace {

// Corners as sub-pixel positions, stage times to the microsecond.
constexpr int kPixelDecimals = 4;
constexpr int kMillisecondDecimals = 3;
// Matrices as the poses (tracking/detection_json.cpp): near float precision.
constexpr int kPoseDigits = 9;

} // namespace

FrameTrace::FrameTrace(const std::filesystem::path& file)
    : file_(file), out_(std::fopen(file.c_str(), "w"), &std::fclose)
{
    if (!out_)
        throw RuntimeError(file.string() + ": cannot write: " + std::strerror(errno));
}

void FrameTrace::write(const FrameReport& r)
{
    Json detections = Json::array();
    for (const TagDetection& d : r.detections) {
        Json corners = Json::array();
        for (const glm::dvec2& corner : d.corners)
            corners.push_back(
                Json::array({jsonDecimals(corner.x, kPixelDecimals), jsonDecimals(corner.y, kPixelDecimals)}));
        Json detection = {{"id", d.id}, {"corners", std::move(corners)}};
        if (d.hasPose)
            addPoseJson(detection, d.cameraFromMarker);
        detections.push_back(std::move(detection));
    }
    Json maps = Json::array();
    for (const MapDetection& map : r.maps)
        maps.push_back(mapDetectionJson(map));
    Json poses = Json::array();
    for (const TrackedPoses::Used& used : r.poses)
        poses.push_back(trackedPoseJson(used, r.mapNames));
    Json objects = Json::array();
    for (const DrawnObject& object : r.objects) {
        Json rows = Json::array();
        for (int row = 0; row < 4; ++row) {
            Json values = Json::array();
            for (int column = 0; column < 4; ++column)
                values.push_back(jsonSignificant(object.cameraFromModel[column][row], kPoseDigits));
            rows.push_back(std::move(values));
        }
        objects.push_back({{"object", object.object}, {"camera_from_model", std::move(rows)}});
    }
    const Json line = {{"frame", r.sequence},
                       {"timestamp_ns", r.timestampNs},
                       {"captured_ns", r.capturedNs},
                       {"objects_drawn", r.objectsDrawn},
                       {"detections", std::move(detections)},
                       {"maps", std::move(maps)},
                       {"detected_frame", r.detectedSequence},
                       {"pose_time_ns", r.poseTimeNs},
                       {"poses", std::move(poses)},
                       {"objects", std::move(objects)},
                       {"stage_ms",
                        {{"capture", jsonDecimals(r.times.captureMs, kMillisecondDecimals)},
                         {"detect", jsonDecimals(r.times.detectMs, kMillisecondDecimals)},
                         {"render", jsonDecimals(r.times.renderMs, kMillisecondDecimals)},
                         {"readback", jsonDecimals(r.times.readbackMs, kMillisecondDecimals)}}}};
    const std::string text = jsonLine(line) + "\n";
    if (std::fwrite(text.data(), 1, text.size(), out_.get()) != text.size())
        throw RuntimeError(file_.string() + ": write failed: " + std::strerror(errno));
}

} // namespace lumar
