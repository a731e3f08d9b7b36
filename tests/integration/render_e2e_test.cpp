// End to end: `lumar render` on the fake camera, checked against the fake camera's exact
// ground truth — detection rate, pose error, and where the model appears in the rendered
// image (measured from the pixels, not from lumar's internal state).
#include <cmath>
#include <fstream>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "capture/fake_camera.h"
#include "config/config.h"
#include "output/frame_writer.h"
#include "run_lumar.h"

namespace lumar {
namespace {

constexpr int kFrames = 30;
constexpr double kBoxSize = 0.06; // metres, the object's longest side on the marker

std::string sceneToml()
{
    const std::string source = LUMAR_SOURCE_DIR;
    return "[camera]\nsource = \"fake\"\nwidth = 1280\nheight = 720\nseed = 7\n"
           "[[camera.fake_tags]]\nid = 0\nsize = 0.16\nposition = [0.0, 0.0]\n"
           "[[markers]]\nid = 0\nsize = 0.16\n"
           "[[objects]]\nname = \"box\"\nmodel = \"" +
           source +
           "/tests/data/models/BoxTextured.glb\"\nmarker = 0\n"
           "size = " +
           std::to_string(kBoxSize) +
           "\n"
           "[environment]\nhdr = \"" +
           source +
           "/daemon/assets/env/venice_sunset_1k.hdr\"\n"
           // The model's silhouette is measured as the pixels that differ from the camera
           // image: without the shadow it casts on the table (DESIGN.md §6.5).
           "[shadows]\nenabled = false\n";
}

double rotationErrorDeg(const glm::dmat3& a, const glm::dmat3& b)
{
    const glm::dmat3 d = glm::transpose(a) * b;
    const double c = std::clamp((d[0][0] + d[1][1] + d[2][2] - 1.0) / 2.0, -1.0, 1.0);
    return std::acos(c) * 180.0 / M_PI;
}

glm::dmat3 jsonMatrix(const nlohmann::json& rows)
{
    glm::dmat3 m;
    for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 3; ++c)
            m[c][r] = rows[r][c].get<double>();
    return m;
}

class RenderEndToEnd : public ::testing::Test {
protected:
    static void SetUpTestSuite()
    {
        dir_ = test::scratchDirectory("render-e2e");
        std::ofstream(dir_ / "scene.toml") << sceneToml();
        result_ =
            test::runLumar({"render", "--config", (dir_ / "scene.toml").string(), "--frames", std::to_string(kFrames),
                            "--out", (dir_ / "frame_%03d.png").string(), "--trace", (dir_ / "trace.jsonl").string()},
                           dir_);
    }
    static std::filesystem::path dir_;
    static test::ProcessResult result_;
};
std::filesystem::path RenderEndToEnd::dir_;
test::ProcessResult RenderEndToEnd::result_;

TEST_F(RenderEndToEnd, ExitsCleanly)
{
    ASSERT_EQ(result_.exitCode, 0) << result_.err;
    EXPECT_NE(result_.out.find("rendered 30 frames"), std::string::npos) << result_.out;
}

TEST_F(RenderEndToEnd, DetectsTheMarkerWithAccuratePose)
{
    ASSERT_EQ(result_.exitCode, 0) << result_.err;
    const Config config = parseConfig(sceneToml(), "scene.toml", dir_);
    const FakeCamera camera(config.camera);
    std::ifstream trace(dir_ / "trace.jsonl");
    std::string line;
    int frames = 0, detected = 0;
    double worstRotationDeg = 0, worstTranslationPct = 0;
    while (std::getline(trace, line)) {
        const auto j = nlohmann::json::parse(line);
        const uint64_t sequence = j["frame"].get<uint64_t>();
        EXPECT_EQ(sequence, uint64_t(frames));
        ++frames;
        for (const auto& d : j["detections"]) {
            if (d["id"] != 0 || !d.contains("R"))
                continue;
            ++detected;
            const TagGroundTruth truth = camera.groundTruth(sequence).at(0);
            worstRotationDeg =
                std::max(worstRotationDeg, rotationErrorDeg(jsonMatrix(d["R"]), truth.cameraFromMarker.R));
            const glm::dvec3 t(d["t"][0].get<double>(), d["t"][1].get<double>(), d["t"][2].get<double>());
            worstTranslationPct = std::max(worstTranslationPct, 100.0 * glm::length(t - truth.cameraFromMarker.t) /
                                                                    glm::length(truth.cameraFromMarker.t));
        }
    }
    EXPECT_EQ(frames, kFrames);
    EXPECT_GE(detected, int(std::ceil(0.95 * kFrames))) << "marker found in " << detected << " of " << frames;
    // A 16 cm tag at 0.5-0.8 m is 200+ px wide; IPPE on sub-pixel corners does much better
    // than these bounds (see the issue note for the measured figures).
    EXPECT_LT(worstRotationDeg, 1.0);
    EXPECT_LT(worstTranslationPct, 1.0);
    RecordProperty("worst_rotation_error_deg", std::to_string(worstRotationDeg));
    RecordProperty("worst_translation_error_pct", std::to_string(worstTranslationPct));
    std::printf("pose error over %d frames: rotation <= %.3f deg, translation <= %.3f %%\n", detected, worstRotationDeg,
                worstTranslationPct);
}

TEST_F(RenderEndToEnd, ModelAppearsWhereGroundTruthPutsIt)
{
    ASSERT_EQ(result_.exitCode, 0) << result_.err;
    const Config config = parseConfig(sceneToml(), "scene.toml", dir_);
    const FakeCamera camera(config.camera);
    Frame raw;
    double worstPx = 0;
    for (int k = 0; k < kFrames; k += 3) {
        char name[32];
        std::snprintf(name, sizeof name, "frame_%03d.png", k);
        const Image8 rendered = readImage(dir_ / name, 3);
        camera.render(uint64_t(k), raw);
        ASSERT_EQ(rendered.width, raw.rgb.width);
        ASSERT_EQ(rendered.height, raw.rgb.height);
        // The model's silhouette: pixels that differ from the camera image. Untouched pixels
        // equal it exactly (UntouchedPixelsAreTheCameraImage), so a
        // sum over the channels above 6 is a drawn pixel; at 24, box texels lit like the table
        // under the camera response were missed and the centroid moved by 3.4 px.
        double sx = 0, sy = 0, n = 0;
        for (int y = 0; y < rendered.height; ++y)
            for (int x = 0; x < rendered.width; ++x) {
                int diff = 0;
                for (int c = 0; c < 3; ++c)
                    diff += std::abs(int(rendered.at(x, y)[c]) - int(raw.rgb.at(x, y)[c]));
                if (diff > 6) {
                    sx += x;
                    sy += y;
                    n += 1;
                }
            }
        ASSERT_GT(n, 500) << "no model visible in frame " << k;
        const TagGroundTruth truth = camera.groundTruth(uint64_t(k)).at(0);
        const glm::dvec3 centre = truth.cameraFromMarker.apply({0.0, 0.0, 0.5 * kBoxSize});
        const glm::dvec2 expected = camera.intrinsics().project(centre);
        const double errorPx = glm::length(glm::dvec2(sx / n, sy / n) - expected);
        worstPx = std::max(worstPx, errorPx);
        // The silhouette centroid of a cube is not exactly the projection of its centre under
        // perspective; at this size (about 80 px) the difference stays under 2 px.
        EXPECT_LT(errorPx, 3.0) << "frame " << k;
    }
    std::printf("model centre vs ground truth: worst %.2f px\n", worstPx);
}

TEST_F(RenderEndToEnd, UntouchedPixelsAreTheCameraImage)
{
    ASSERT_EQ(result_.exitCode, 0) << result_.err;
    const Config config = parseConfig(sceneToml(), "scene.toml", dir_);
    const FakeCamera camera(config.camera);
    Frame raw;
    camera.render(0, raw);
    const Image8 rendered = readImage(dir_ / "frame_000.png", 3);
    // The top-left corner is far from the model in every frame of the trajectory.
    for (int y = 0; y < 40; ++y)
        for (int x = 0; x < 40; ++x)
            for (int c = 0; c < 3; ++c)
                ASSERT_EQ(rendered.at(x, y)[c], raw.rgb.at(x, y)[c]) << x << "," << y;
}

} // namespace
} // namespace lumar
