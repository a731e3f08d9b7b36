#include "tracking/detection_json.h"

namespace lumar {
namespace {

// Significant digits: corners and margins are sub-pixel measurements, the pose is kept to
// near float precision so that consumers can re-project without visible loss.
constexpr int kPixelDigits = 6;
constexpr int kPoseDigits = 9;

Json detectionJson(const TagDetection& d)
{
    Json corners = Json::array();
    for (const glm::dvec2& corner : d.corners)
        corners.push_back(
            Json::array({jsonSignificant(corner.x, kPixelDigits), jsonSignificant(corner.y, kPixelDigits)}));
    Json json = {{"id", d.id},
                 {"hamming", d.hamming},
                 {"margin", jsonSignificant(d.decisionMargin, kPixelDigits)},
                 {"corners", std::move(corners)}};
    if (d.hasPose)
        addPoseJson(json, d.cameraFromMarker);
    return json;
}

} // namespace

void addPoseJson(Json& detection, const Pose& cameraFromMarker)
{
    const auto number = [](double value) { return jsonSignificant(value, kPoseDigits); };
    const glm::dmat3& R = cameraFromMarker.R; // glm: R[column][row]
    Json rows = Json::array();
    for (int row = 0; row < 3; ++row)
        rows.push_back(Json::array({number(R[0][row]), number(R[1][row]), number(R[2][row])}));
    detection["R"] = std::move(rows);
    const glm::dvec3& t = cameraFromMarker.t;
    detection["t"] = Json::array({number(t.x), number(t.y), number(t.z)});
}

Json mapDetectionJson(const MapDetection& map)
{
    Json json = {
        {"map", map.name}, {"tags", map.tagIds}, {"error_px", jsonSignificant(map.reprojectionErrorPx, kPixelDigits)}};
    addPoseJson(json, map.cameraFromMap);
    return json;
}

Json trackedPoseJson(const TrackedPoses::Used& used, const std::vector<std::string>& mapNames)
{
    Json json = Json::object();
    if (TrackedPoses::isMapKey(used.key)) {
        const size_t index = size_t(TrackedPoses::mapIndex(used.key));
        json["map"] = index < mapNames.size() ? mapNames[index] : std::to_string(index);
    } else {
        json["id"] = used.key;
    }
    json["last_seen"] = used.lastSeen;
    addPoseJson(json, used.cameraFromMarker);
    return json;
}

Json detectionsJson(const std::string& file, const std::vector<TagDetection>& detections)
{
    Json list = Json::array();
    for (const TagDetection& d : detections)
        list.push_back(detectionJson(d));
    return {{"file", file}, {"detections", std::move(list)}};
}

std::string detectionsToJson(const std::string& file, const std::vector<TagDetection>& detections)
{
    return jsonLine(detectionsJson(file, detections));
}

} // namespace lumar
