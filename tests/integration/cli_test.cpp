// The lumar command line as a user meets it: help, exit codes, and bad input reported in one
// clear line naming the file — never a crash.
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <system_error>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <sys/wait.h>

#include "run_lumar.h"

namespace lumar {
namespace {

using test::runLumar;

const std::string kSource = LUMAR_SOURCE_DIR;
const std::string kBox = kSource + "/tests/data/models/BoxTextured.glb";
const std::string kHdr = kSource + "/daemon/assets/env/venice_sunset_1k.hdr";

std::string sceneWith(const std::string& model, const std::string& hdr)
{
    return "[camera]\nwidth = 320\nheight = 240\n[[camera.fake_tags]]\nid = 0\nsize = 0.16\nposition = [0.0, 0.0]\n"
           "[[markers]]\nid = 0\nsize = 0.16\n"
           "[[objects]]\nmodel = \"" +
           model +
           "\"\nmarker = 0\nsize = 0.1\n"
           "[environment]\nhdr = \"" +
           hdr + "\"\n";
}

size_t lineCount(const std::string& s)
{
    size_t n = 0;
    for (char c : s)
        n += c == '\n';
    return n;
}

TEST(Cli, HelpForEveryCommand)
{
    const auto dir = test::scratchDirectory("help");
    for (const char* command : {"render", "run", "check-config", "detect", "bench", "probe", "calibrate"}) {
        const auto r = runLumar({command, "--help"}, dir);
        EXPECT_EQ(r.exitCode, 0) << command;
        EXPECT_NE(r.out.find("usage: lumar"), std::string::npos) << command;
    }
    EXPECT_EQ(runLumar({"--help"}, dir).exitCode, 0);
    EXPECT_EQ(runLumar({}, dir).exitCode, 2);
    EXPECT_EQ(runLumar({"frobnicate"}, dir).exitCode, 2);
    EXPECT_EQ(runLumar({"render", "--no-such-option"}, dir).exitCode, 2);
    EXPECT_EQ(runLumar({"render"}, dir).exitCode, 2) << "--out is required";
}

TEST(Cli, CheckConfigAcceptsTheShippedExample)
{
    const auto dir = test::scratchDirectory("check-ok");
    const auto r = runLumar({"check-config", kSource + "/daemon/assets/lumar.toml"}, dir);
    EXPECT_EQ(r.exitCode, 0) << r.err;
    EXPECT_NE(r.out.find(": ok"), std::string::npos);
}

TEST(Cli, CheckConfigReportsFileAndLine)
{
    const auto dir = test::scratchDirectory("check-bad");
    const auto file = dir / "bad.toml";
    std::ofstream(file) << "[camera]\nwidth = 1280\nheight = \"tall\"\n";
    const auto r = runLumar({"check-config", file.string()}, dir);
    EXPECT_EQ(r.exitCode, 2);
    EXPECT_EQ(r.err.rfind(file.string() + ":3:", 0), 0u) << r.err;
    EXPECT_EQ(lineCount(r.err), 1u) << r.err;
}

// An [[objects]] animation the model does not have is named with its file, line and key, as
// the daemon's load would refuse it; an animation the model has passes.
TEST(Cli, CheckConfigNamesAnUnknownAnimation)
{
    const auto dir = test::scratchDirectory("check-animation");
    const std::string skin = kSource + "/tests/data/khronos/SimpleSkin/SimpleSkin.gltf";
    const auto check = [&](const std::string& animation) {
        const auto file = dir / "animated.toml";
        std::ofstream(file) << "[[markers]]\nid = 0\nsize = 0.16\n"
                               "[[objects]]\nmodel = \"" +
                                   kBox +
                                   "\"\nmarker = 0\n"
                                   "[[objects]]\nmodel = \"" +
                                   skin + "\"\nmarker = 0\nsize = 0.1\nanimation = " + animation + "\n";
        return runLumar({"check-config", file.string()}, dir);
    };
    for (const std::string bad : {"\"Wave\"", "3"}) {
        SCOPED_TRACE(bad);
        const auto r = check(bad);
        EXPECT_EQ(r.exitCode, 2);
        EXPECT_EQ(r.err.rfind((dir / "animated.toml").string() + ":11: objects[1].animation: ", 0), 0u) << r.err;
        EXPECT_NE(r.err.find("SimpleSkin.gltf"), std::string::npos) << r.err;
        EXPECT_EQ(lineCount(r.err), 1u) << r.err;
    }
    for (const std::string good : {"0", "\"all\"", "\"none\""}) {
        const auto r = check(good);
        EXPECT_EQ(r.exitCode, 0) << good << ": " << r.err;
    }
}

struct BadInputCase {
    const char* name;
    std::string mentions; // what the one-line error must name
};

class RenderBadInput : public ::testing::Test {
protected:
    test::ProcessResult renderWith(const std::string& toml)
    {
        dir_ = test::scratchDirectory(::testing::UnitTest::GetInstance()->current_test_info()->name());
        std::ofstream(dir_ / "scene.toml") << toml;
        return runLumar({"render", "--config", (dir_ / "scene.toml").string(), "--frames", "2", "--out",
                         (dir_ / "out.png").string()},
                        dir_);
    }
    void expectBadInput(const test::ProcessResult& r, const std::string& mentions)
    {
        EXPECT_EQ(r.exitCode, 2) << r.err;
        EXPECT_NE(r.err.find(mentions), std::string::npos) << r.err;
        EXPECT_EQ(r.err.find("Segmentation"), std::string::npos);
        EXPECT_FALSE(std::filesystem::exists(dir_ / "out.png")) << "no output from a rejected configuration";
    }
    std::filesystem::path dir_;
};

TEST_F(RenderBadInput, SyntaxError)
{
    const auto r = renderWith("[camera\nwidth = 3\n");
    expectBadInput(r, "scene.toml:1:");
}

TEST_F(RenderBadInput, MissingModel)
{
    const auto r = renderWith(sceneWith("/nonexistent/model.glb", kHdr));
    expectBadInput(r, "model.glb");
}

TEST_F(RenderBadInput, CorruptGltf)
{
    dir_ = test::scratchDirectory("corrupt-gltf");
    const auto model = dir_ / "broken.glb";
    std::ofstream(model) << "glTF this is not a real binary glTF file";
    const auto r = renderWith(sceneWith(model.string(), kHdr));
    expectBadInput(r, "broken.glb");
}

TEST_F(RenderBadInput, CorruptHdr)
{
    dir_ = test::scratchDirectory("corrupt-hdr");
    const auto hdr = dir_ / "broken.hdr";
    std::ofstream(hdr) << "#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 512 +X 1024\n\x01\x02";
    const auto r = renderWith(sceneWith(kBox, hdr.string()));
    expectBadInput(r, "broken.hdr");
}

// Without a usable EGL/GLES 3 the renderer cannot start: a runtime failure (exit 1) with one
// clear line, not a crash. Mesa is made to fail in two places: no EGL vendor (libglvnd finds
// no Mesa), and no driver behind the surfaceless display.
TEST(Cli, NoEglIsAClearRuntimeError)
{
    const auto dir = test::scratchDirectory("no-egl");
    for (const char* environment : {"__EGL_VENDOR_LIBRARY_DIRS=/nonexistent", "LIBGL_DRIVERS_PATH=/nonexistent"}) {
        const auto r = runLumar({"render", "--frames", "1", "--out", (dir / "out.png").string()}, dir, {environment});
        EXPECT_EQ(r.exitCode, 1) << environment << "\n" << r.err;
        EXPECT_NE(r.err.find("lumar: "), std::string::npos) << r.err;
        EXPECT_NE(r.err.find("EGL"), std::string::npos) << r.err;
        EXPECT_FALSE(std::filesystem::exists(dir / "out.png"));
    }
}

TEST(Cli, BenchPrintsItsJsonReport)
{
    const auto dir = test::scratchDirectory("bench");
    std::ofstream(dir / "scene.toml") << sceneWith(kBox, kHdr);
    const auto r = runLumar({"bench", "--config", (dir / "scene.toml").string(), "--frames", "3", "--warmup", "1",
                             "--json", "--log-level", "warn"},
                            dir);
    ASSERT_EQ(r.exitCode, 0) << r.err;
    const auto j = nlohmann::json::parse(r.out);
    EXPECT_EQ(j["frames"], 3);
    EXPECT_EQ(j["width"], 320);
    EXPECT_GT(j["fps"].get<double>(), 0.0);
    EXPECT_LE(j["frame_ms"]["p50"].get<double>(), j["frame_ms"]["p99"].get<double>());
    for (const char* stage : {"capture", "detect", "render", "readback"})
        EXPECT_GE(j["stages_ms"][stage].get<double>(), 0.0) << stage;
    // Profiled: every render stage has its wall and CPU time; the frame drew something.
    for (const char* stage : {"env_maps", "sh", "prefilter", "background", "shading", "shadows", "receivers", "post"}) {
        EXPECT_GE(j["stages_ms"][stage].get<double>(), 0.0) << stage;
        EXPECT_GE(j["stages_cpu_ms"][stage].get<double>(), 0.0) << stage;
    }
    EXPECT_GT(j["stages_cpu_ms"]["shading"].get<double>(), 0.0);
    EXPECT_GT(j["cpu_ms_per_frame"].get<double>(), 0.0);
    EXPECT_GT(j["rss_mb"].get<double>(), 0.0);
    EXPECT_GE(j["peak_rss_mb"].get<double>(), j["rss_mb"].get<double>());
    // The resident figure split into the process's own memory and mapped files' pages (read a
    // moment apart: the detection thread may allocate between the reads).
    EXPECT_GT(j["rss_anon_mb"].get<double>(), 0.0);
    EXPECT_GT(j["rss_file_mb"].get<double>(), 0.0);
    EXPECT_NEAR(j["rss_anon_mb"].get<double>() + j["rss_file_mb"].get<double>(), j["rss_mb"].get<double>(), 1.0);
    EXPECT_EQ(j["source"], "live");
    EXPECT_TRUE(j["replay"].is_null());
    // Live: nothing replayed to leave out; the heap's figures are there.
    EXPECT_DOUBLE_EQ(j["peak_rss_less_replay_mb"].get<double>(), j["peak_rss_mb"].get<double>());
    EXPECT_GT(j["heap"]["in_use_mb"].get<double>(), 0.0);
    EXPECT_GE(j["heap"]["free_mb"].get<double>(), 0.0);
    // Capture to readback: each frame's latency covers at least its own render.
    ASSERT_TRUE(j["latency_ms"].is_object()) << r.out;
    EXPECT_GT(j["latency_ms"]["p50"].get<double>(), 0.0);
    EXPECT_LE(j["latency_ms"]["p50"].get<double>(), j["latency_ms"]["p99"].get<double>());
}

TEST(Cli, BenchReplaysFramesFromMemory)
{
    const auto dir = test::scratchDirectory("bench_replay");
    std::ofstream(dir / "scene.toml") << sceneWith(kBox, kHdr);
    const auto r = runLumar({"bench", "--config", (dir / "scene.toml").string(), "--frames", "4", "--warmup", "1",
                             "--replay", "--replay-frames", "2", "--json", "--log-level", "warn"},
                            dir);
    ASSERT_EQ(r.exitCode, 0) << r.err;
    const auto j = nlohmann::json::parse(r.out);
    EXPECT_EQ(j["source"], "replay");
    EXPECT_EQ(j["camera"], "fake");
    EXPECT_EQ(j["replay"]["frames"], 2);
    EXPECT_GT(j["replay"]["mb"].get<double>(), 0.0);
    // The device's figure leaves the replayed frames out (rounding to 0.1 MB aside).
    EXPECT_NEAR(j["peak_rss_less_replay_mb"].get<double>(),
                j["peak_rss_mb"].get<double>() - j["replay"]["mb"].get<double>(), 0.11);
    EXPECT_EQ(j["frames"], 4);
    ASSERT_TRUE(j["latency_ms"].is_object()) << r.out;
    EXPECT_GT(j["latency_ms"]["p50"].get<double>(), 0.0);
    EXPECT_LE(j["latency_ms"]["p50"].get<double>(), j["latency_ms"]["p99"].get<double>());
    EXPECT_LE(j["latency_ms"]["p99"].get<double>(), 60'000.0) << "a minute would be a stale clock";
    // A replay length out of range is a usage error with one line.
    const auto bad = runLumar({"bench", "--replay", "--replay-frames", "0"}, dir);
    EXPECT_EQ(bad.exitCode, 2) << bad.err;
    EXPECT_NE(bad.err.find("--replay-frames"), std::string::npos) << bad.err;
}

TEST(Cli, BenchTrackingPrintsATableAndJson)
{
    const auto dir = test::scratchDirectory("bench_tracking");
    const std::vector<std::string> small = {"bench",    "--tracking", "--frames-per-condition", "2", "--width", "320",
                                            "--height", "180"};
    const auto table = runLumar(small, dir);
    ASSERT_EQ(table.exitCode, 0) << table.err;
    EXPECT_NE(table.out.find("| clean | lumar |"), std::string::npos) << table.out;
    EXPECT_NE(table.out.find("| overall | apriltag |"), std::string::npos) << table.out;
    auto withJson = small;
    withJson.emplace_back("--json");
    const auto json = runLumar(withJson, dir);
    ASSERT_EQ(json.exitCode, 0) << json.err;
    const auto j = nlohmann::json::parse(json.out);
    EXPECT_EQ(j["frames_per_condition"], 2);
    EXPECT_EQ(j["rows"].size(), (j["conditions"].size() + 1) * j["detectors"].size());
    EXPECT_EQ(runLumar({"bench", "--tracking", "--frames-per-condition", "0"}, dir).exitCode, 2);
}

TEST(Cli, BenchTrackingNamesTheBenchmarkWhereItIsNotBuilt)
{
    // As installed: a lumar without lumar-bench-tracking next to it (a hard link, or a copy
    // across file systems; /proc/self/exe names the link).
    const auto dir = test::scratchDirectory("bench_tracking_alone");
    const auto lumar = dir / "lumar";
    std::error_code ec;
    std::filesystem::create_hard_link(LUMAR_BINARY, lumar, ec);
    if (ec)
        std::filesystem::copy_file(LUMAR_BINARY, lumar);
    const std::string command = test::shellQuote(lumar.string()) + " bench --tracking >" +
                                test::shellQuote((dir / "out.txt").string()) + " 2>" +
                                test::shellQuote((dir / "err.txt").string());
    const int status = std::system(command.c_str());
    EXPECT_EQ(WIFEXITED(status) ? WEXITSTATUS(status) : -1, 1);
    const std::string err = test::readText(dir / "err.txt");
    EXPECT_NE(err.find("lumar-bench-tracking"), std::string::npos) << err;
    EXPECT_EQ(lineCount(err), 1u) << err;
    std::filesystem::remove_all(dir);
}

TEST(Cli, CalibrateWritesAYamlThatLoads)
{
    const auto dir = test::scratchDirectory("calibrate");
    const auto out = dir / "camera.yaml";
    const auto r = runLumar({"calibrate", "--images", kSource + "/tests/data/calib/chessboard", "--board", "9x6",
                             "--square", "0.025", "--out", out.string()},
                            dir);
    ASSERT_EQ(r.exitCode, 0) << r.err;
    EXPECT_NE(r.out.find("left01.jpg"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("wrote"), std::string::npos) << r.out;
    // The written calibration is usable by the other commands.
    const auto check = runLumar(
        {"detect", "--tag-size", "0.1", "--calib", out.string(), kSource + "/tests/data/calib/chessboard/left01.jpg"},
        dir);
    EXPECT_EQ(check.exitCode, 0) << check.err;
    const auto bad = runLumar({"calibrate", "--images", dir.string(), "--board", "9x6", "--square", "0.025", "--out",
                               (dir / "x.yaml").string()},
                              dir);
    EXPECT_EQ(bad.exitCode, 2) << bad.err;
}

TEST(Cli, DetectPrintsOneJsonObjectPerImage)
{
    const auto dir = test::scratchDirectory("detect");
    const std::string photo = kSource + "/tests/data/apriltag/real/33369213973_9d9bb4cc96_c.jpg";
    const auto r = runLumar({"detect", "--tag-size", "0.16", photo, "/nonexistent.png"}, dir);
    EXPECT_EQ(r.exitCode, 2) << "one image was unreadable";
    EXPECT_NE(r.err.find("/nonexistent.png"), std::string::npos) << r.err;
    ASSERT_EQ(lineCount(r.out), 1u) << r.out;
    const auto j = nlohmann::json::parse(r.out);
    EXPECT_EQ(j["file"], photo);
    // The AprilTag library's own expected detections for this photo: 12 tags, all id 0.
    ASSERT_EQ(j["detections"].size(), 12u);
    for (const auto& d : j["detections"]) {
        EXPECT_EQ(d["id"], 0);
        EXPECT_EQ(d["corners"].size(), 4u);
        EXPECT_EQ(d["R"].size(), 3u);
        EXPECT_GT(d["t"][2].get<double>(), 0.0) << "tags lie in front of the camera";
    }
}

} // namespace
} // namespace lumar
