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
    const Json line = {{"frame", r.sequence},
                       {"timestamp_ns", r.timestampNs},
                       {"objects_drawn", r.objectsDrawn},
                       {"detections", std::move(detections)},
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
