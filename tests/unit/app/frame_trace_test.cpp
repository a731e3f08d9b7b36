#include <fstream>
#include <limits>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "frame_trace.h"
#include "unit/capture/temp_dir.h"

namespace lumar {
namespace {

FrameReport aReport()
{
    FrameReport r;
    r.sequence = 41;
    r.timestampNs = 1'234'567'890'123;
    r.objectsDrawn = 1;
    TagDetection posed;
    posed.id = 3;
    posed.corners = {glm::dvec2{1.23456, 2.0}, {100.125, 2.0}, {100.0, 99.5}, {0.00004, -0.5}};
    posed.hasPose = true;
    posed.cameraFromMarker.R =
        glm::dmat3(glm::dvec3(0.1, 0.4, 0.7), glm::dvec3(0.2, 0.5, 0.8), glm::dvec3(0.3, 0.6, 0.9));
    posed.cameraFromMarker.t = {0.1, -0.2, 1.23456789012};
    TagDetection unposed;
    unposed.id = 7;
    r.detections = {posed, unposed};
    r.times = {1.5, 2.25, 10.0004, 0.1236};
    return r;
}

std::vector<nlohmann::json> traceLines(const std::vector<FrameReport>& reports)
{
    const test::TempDir dir;
    {
        FrameTrace trace(dir / "trace.jsonl");
        for (const FrameReport& r : reports)
            trace.write(r);
    }
    std::ifstream in(dir / "trace.jsonl");
    std::vector<nlohmann::json> lines;
    for (std::string line; std::getline(in, line);)
        lines.push_back(nlohmann::json::parse(line));
    return lines;
}

TEST(FrameTrace, OneJsonObjectPerFrame)
{
    const auto lines = traceLines({aReport(), aReport()});
    ASSERT_EQ(lines.size(), 2u);
    const nlohmann::json& j = lines[0];
    EXPECT_EQ(j["frame"], 41);
    EXPECT_EQ(j["timestamp_ns"], 1'234'567'890'123);
    EXPECT_EQ(j["objects_drawn"], 1);
    ASSERT_EQ(j["detections"].size(), 2u);
    const nlohmann::json& d = j["detections"][0];
    EXPECT_EQ(d["id"], 3);
    EXPECT_EQ(d["corners"][0][0].get<double>(), 1.2346) << "corners to 4 decimals";
    EXPECT_EQ(d["corners"][1][0].get<double>(), 100.125);
    EXPECT_EQ(d["corners"][3][0].get<double>(), 0.0);
    EXPECT_EQ(d["corners"][3][1].get<double>(), -0.5);
    EXPECT_EQ(d["R"][0], nlohmann::json::parse("[0.1,0.2,0.3]")) << "R row-major";
    EXPECT_EQ(d["R"][2], nlohmann::json::parse("[0.7,0.8,0.9]"));
    EXPECT_EQ(d["t"][2].get<double>(), 1.23456789) << "the pose to 9 significant digits";
    EXPECT_FALSE(j["detections"][1].contains("R")) << "no pose, no R";
    EXPECT_EQ(j["stage_ms"]["capture"].get<double>(), 1.5);
    EXPECT_EQ(j["stage_ms"]["render"].get<double>(), 10.0) << "stage times to 3 decimals";
    EXPECT_EQ(j["stage_ms"]["readback"].get<double>(), 0.124);
}

TEST(FrameTrace, NonFiniteNumbersBecomeNull)
{
    FrameReport r = aReport();
    r.detections[0].corners[2].x = std::numeric_limits<double>::quiet_NaN();
    r.detections[0].cameraFromMarker.t.z = std::numeric_limits<double>::infinity();
    r.times.detectMs = std::numeric_limits<double>::quiet_NaN();
    const auto lines = traceLines({r});
    ASSERT_EQ(lines.size(), 1u);
    const nlohmann::json& d = lines[0]["detections"][0];
    EXPECT_TRUE(d["corners"][2][0].is_null());
    EXPECT_EQ(d["corners"][2][1].get<double>(), 99.5);
    EXPECT_TRUE(d["t"][2].is_null());
    EXPECT_TRUE(lines[0]["stage_ms"]["detect"].is_null());
}

// Issue 19: the measured map poses, the filtered poses drawn with (tags by id, maps by name)
// and the objects' transforms as the renderer received them.
TEST(FrameTrace, CarriesMapsFilteredPosesAndObjects)
{
    FrameReport r = aReport();
    r.capturedNs = 77;
    r.detectedSequence = 40;
    r.poseTimeNs = 1'234'567'990'123;
    MapDetection map;
    map.index = 0;
    map.name = "board";
    map.tagIds = {0, 1};
    map.reprojectionErrorPx = 0.25;
    map.cameraFromMap.t = {0.0, 0.1, 0.6};
    r.maps = {map};
    r.mapNames = {"board"};
    TrackedPoses::Used tag{3, {}, 40};
    tag.cameraFromMarker.t = {0.1, -0.2, 1.2};
    TrackedPoses::Used board{TrackedPoses::mapKey(0), {}, 41};
    r.poses = {board, tag};
    DrawnObject object;
    object.object = 2;
    object.marker = 3;
    object.cameraFromModel[3] = glm::dvec4(0.1, -0.2, 1.25, 1.0);
    r.objects = {object};
    const auto lines = traceLines({r});
    ASSERT_EQ(lines.size(), 1u);
    const nlohmann::json& j = lines[0];
    EXPECT_EQ(j["captured_ns"], 77);
    EXPECT_EQ(j["detected_frame"], 40);
    EXPECT_EQ(j["pose_time_ns"], 1'234'567'990'123);
    ASSERT_EQ(j["maps"].size(), 1u);
    EXPECT_EQ(j["maps"][0]["map"], "board");
    EXPECT_EQ(j["maps"][0]["tags"], nlohmann::json::parse("[0,1]"));
    EXPECT_EQ(j["maps"][0]["t"][2].get<double>(), 0.6);
    ASSERT_EQ(j["poses"].size(), 2u);
    EXPECT_EQ(j["poses"][0]["map"], "board");
    EXPECT_EQ(j["poses"][0]["last_seen"], 41);
    EXPECT_EQ(j["poses"][1]["id"], 3);
    EXPECT_EQ(j["poses"][1]["t"][2].get<double>(), 1.2);
    ASSERT_EQ(j["objects"].size(), 1u);
    EXPECT_EQ(j["objects"][0]["object"], 2);
    EXPECT_EQ(j["objects"][0]["camera_from_model"][2][3].get<double>(), 1.25) << "row-major, translation last";
    EXPECT_EQ(j["objects"][0]["camera_from_model"][3], nlohmann::json::parse("[0,0,0,1]"));
}

} // namespace
} // namespace lumar
