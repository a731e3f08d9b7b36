// The tracker scored whole (issue 19): `lumar render --trace` records, per frame, the raw
// detections and map poses, the filtered poses the objects were placed with, and each
// object's transform as the renderer received it. The filtered pose in the trace must be the
// one the renderer placed the object with, for an object on a tag and one on a [[maps]] board;
// `lumar detect --sequence --config` prints the filtered and map poses too.
#include <fstream>
#include <optional>
#include <sstream>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "config/config.h"
#include "core/pose.h"
#include "gles_renderer/assets/builtin_shapes.h"
#include "object_placement.h"
#include "run_lumar.h"

namespace lumar {
namespace {

constexpr int kFrames = 12;

std::string sceneToml()
{
    const std::string source = LUMAR_SOURCE_DIR;
    return "[camera]\nsource = \"fake\"\nwidth = 640\nheight = 360\nseed = 3\n"
           "[[camera.fake_tags]]\nid = 0\nsize = 0.1\nposition = [-0.08, 0.0]\n"
           "[[camera.fake_tags]]\nid = 1\nsize = 0.1\nposition = [0.08, 0.0]\n"
           "[[markers]]\nid = 0\nsize = 0.1\n"
           "[[maps]]\nname = \"pair\"\n"
           "[[maps.tags]]\nid = 0\nsize = 0.1\nposition = [-0.08, 0.0, 0.0]\n"
           "[[maps.tags]]\nid = 1\nsize = 0.1\nposition = [0.08, 0.0, 0.0]\n"
           "[[objects]]\nname = \"on_tag\"\nmodel = \"builtin:cube\"\nmarker = 0\nsize = 0.04\n"
           "[[objects]]\nname = \"on_map\"\nmodel = \"builtin:sphere\"\nmap = \"pair\"\nsize = 0.05\n"
           "offset = [0.0, -0.1, 0.0]\n"
           "[environment]\nhdr = \"" +
           source + "/daemon/assets/env/venice_sunset_1k.hdr\"\n[shadows]\nenabled = false\n";
}

Pose jsonPose(const nlohmann::json& j)
{
    Pose pose;
    for (int r = 0; r < 3; ++r) {
        for (int c = 0; c < 3; ++c)
            pose.R[c][r] = j["R"][r][c].get<double>();
        pose.t[r] = j["t"][r].get<double>();
    }
    return pose;
}

glm::dmat4 jsonMatrix4(const nlohmann::json& rows)
{
    glm::dmat4 m;
    for (int r = 0; r < 4; ++r)
        for (int c = 0; c < 4; ++c)
            m[c][r] = rows[r][c].get<double>();
    return m;
}

std::optional<Pose> posedAs(const nlohmann::json& poses, const std::string& field, const nlohmann::json& value)
{
    for (const auto& p : poses)
        if (p.contains(field) && p[field] == value)
            return jsonPose(p);
    return std::nullopt;
}

class TracePoses : public ::testing::Test {
protected:
    static void SetUpTestSuite()
    {
        dir_ = test::scratchDirectory("trace-poses");
        std::ofstream(dir_ / "scene.toml") << sceneToml();
        result_ =
            test::runLumar({"render", "--config", (dir_ / "scene.toml").string(), "--frames", std::to_string(kFrames),
                            "--out", (dir_ / "frame_%03d.png").string(), "--trace", (dir_ / "trace.jsonl").string()},
                           dir_);
    }
    static std::vector<nlohmann::json> lines()
    {
        std::ifstream trace(dir_ / "trace.jsonl");
        std::vector<nlohmann::json> result;
        for (std::string line; std::getline(trace, line);)
            result.push_back(nlohmann::json::parse(line));
        return result;
    }
    static std::filesystem::path dir_;
    static test::ProcessResult result_;
};
std::filesystem::path TracePoses::dir_;
test::ProcessResult TracePoses::result_;

// Each object's transform as handed to the renderer is its marker's (or map's) filtered pose
// in the trace times the object's placement on it (app/object_placement.h), within 1e-6.
TEST_F(TracePoses, FilteredPoseIsThePoseTheRendererPlacedTheObjectWith)
{
    ASSERT_EQ(result_.exitCode, 0) << result_.err;
    const Config config = parseConfig(sceneToml(), "scene.toml", dir_);
    std::vector<glm::dmat4> markerFromModels;
    for (const ObjectConfig& object : config.objects) {
        const std::string shape = object.model.string().substr(kBuiltinModelPrefix.size());
        const GltfModel model = makeBuiltinShape(shape);
        markerFromModels.push_back(markerFromModel(object, model.boundsMin, model.boundsMax));
    }
    const auto trace = lines();
    ASSERT_EQ(trace.size(), size_t(kFrames));
    int checked[2] = {0, 0}, mapsMeasured = 0;
    for (const auto& j : trace) {
        SCOPED_TRACE("frame " + j["frame"].dump());
        EXPECT_TRUE(j.contains("captured_ns"));
        EXPECT_EQ(j["detected_frame"], j["frame"]) << "lumar render detects every frame in the loop";
        mapsMeasured += int(j["maps"].size());
        for (const auto& m : j["maps"]) {
            EXPECT_EQ(m["map"], "pair");
            EXPECT_EQ(m["tags"], nlohmann::json::parse("[0,1]"));
        }
        for (const auto& object : j["objects"]) {
            const int index = object["object"].get<int>();
            ASSERT_TRUE(index == 0 || index == 1);
            const auto pose = index == 0 ? posedAs(j["poses"], "id", 0) : posedAs(j["poses"], "map", "pair");
            ASSERT_TRUE(pose) << "object " << index << " drawn without its pose in the trace";
            const glm::dmat4 expected = pose->matrix() * markerFromModels[size_t(index)];
            const glm::dmat4 received = jsonMatrix4(object["camera_from_model"]);
            for (int c = 0; c < 4; ++c)
                for (int r = 0; r < 4; ++r)
                    EXPECT_NEAR(received[c][r], expected[c][r], 1e-6)
                        << "object " << index << " [" << r << "][" << c << "]";
            ++checked[index];
        }
    }
    EXPECT_GE(checked[0], kFrames - 1) << "the object on tag 0 drawn on most frames";
    EXPECT_GE(checked[1], kFrames - 1) << "the object on map 'pair' drawn on most frames";
    EXPECT_GE(mapsMeasured, kFrames - 1) << "the map's measured pose in the trace";
}

// The filtered pose of a still-standing filter is not the raw one: the trace carries both,
// and they agree to the filter's smoothing (a few millimetres here).
TEST_F(TracePoses, FilteredAndRawPosesAreBothRecorded)
{
    ASSERT_EQ(result_.exitCode, 0) << result_.err;
    int compared = 0;
    for (const auto& j : lines()) {
        const auto filtered = posedAs(j["poses"], "id", 0);
        for (const auto& d : j["detections"])
            if (d["id"] == 0 && d.contains("R") && filtered) {
                EXPECT_LT(glm::length(jsonPose(d).t - filtered->t), 0.02);
                ++compared;
            }
        const auto map = posedAs(j["poses"], "map", "pair");
        EXPECT_TRUE(map.has_value()) << "frame " << j["frame"];
    }
    EXPECT_GE(compared, kFrames - 1);
}

// lumar detect on the rendered frames as a sequence, with the scene's config: the map's pose
// and the filtered poses per tag and map on every line.
TEST_F(TracePoses, DetectOnASequencePrintsMapAndFilteredPoses)
{
    ASSERT_EQ(result_.exitCode, 0) << result_.err;
    std::vector<std::string> args{"detect",     "--tag-size", "0.1",
                                  "--sequence", "--config",   (dir_ / "scene.toml").string()};
    for (int i = 0; i < 4; ++i) {
        char name[32];
        std::snprintf(name, sizeof name, "frame_%03d.png", i);
        args.push_back((dir_ / name).string());
    }
    const test::ProcessResult detect = test::runLumar(args, dir_);
    ASSERT_EQ(detect.exitCode, 0) << detect.err;
    std::istringstream out(detect.out);
    int lineCount = 0;
    for (std::string line; std::getline(out, line); ++lineCount) {
        const auto j = nlohmann::json::parse(line);
        EXPECT_EQ(j["frame"], lineCount);
        ASSERT_EQ(j["maps"].size(), 1u) << line;
        EXPECT_EQ(j["maps"][0]["map"], "pair");
        EXPECT_TRUE(posedAs(j["filtered"], "map", "pair")) << line;
        EXPECT_TRUE(posedAs(j["filtered"], "id", 1)) << line;
    }
    EXPECT_EQ(lineCount, 4);
}

} // namespace
} // namespace lumar
