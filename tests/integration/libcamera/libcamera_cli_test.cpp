// `lumar probe` and `lumar render` with the libcamera source, run as a user would. Without
// cameras, render must fail as a runtime failure (exit 1) with one error line, quickly.
#include <chrono>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "capture/libcamera/libcamera_probe.h"
#include "integration/run_lumar.h"

namespace lumar {
namespace {

// The error lines of a run's stderr ("lumar: ..."; the rest is the log).
std::vector<std::string> errorLines(const std::string& s)
{
    std::vector<std::string> lines;
    std::istringstream in(s);
    for (std::string line; std::getline(in, line);)
        if (line.rfind("lumar: ", 0) == 0)
            lines.push_back(line);
    return lines;
}

TEST(LibcameraCli, ProbeListsTheLibcameraSection)
{
    const auto dir = test::scratchDirectory("libcamera-probe");
    const auto r = test::runLumar({"probe"}, dir);
    ASSERT_EQ(r.exitCode, 0) << r.err;
    const size_t section = r.out.find("\nlibcamera cameras (libcamera v");
    ASSERT_NE(section, std::string::npos) << r.out;
    const LibcameraProbeInfo info = probeLibcamera();
    if (info.cameras.empty()) {
        EXPECT_NE(r.out.find(":\n  none: libcamera: no cameras found (libcamera v", section), std::string::npos)
            << r.out;
    } else {
        EXPECT_NE(r.out.find("\n  " + info.cameras.front().id + ": ", section), std::string::npos) << r.out;
    }
}

TEST(LibcameraCli, CheckConfigAcceptsTheSource)
{
    const auto dir = test::scratchDirectory("libcamera-check");
    std::ofstream(dir / "scene.toml") << "[camera]\nsource = \"libcamera\"\ndevice = \"some camera id\"\n";
    const auto r = test::runLumar({"check-config", (dir / "scene.toml").string()}, dir);
    EXPECT_EQ(r.exitCode, 0) << r.err;
}

TEST(LibcameraCli, RenderWithoutACameraIsARuntimeFailureInOneLine)
{
    if (!probeLibcamera().cameras.empty())
        GTEST_SKIP() << "this machine has libcamera cameras";
    const auto dir = test::scratchDirectory("libcamera-render");
    std::ofstream(dir / "scene.toml") << "[camera]\nsource = \"libcamera\"\nwidth = 640\nheight = 480\n";
    const auto start = std::chrono::steady_clock::now();
    const auto r = test::runLumar(
        {"render", "--config", (dir / "scene.toml").string(), "--frames", "3", "--out", (dir / "out.png").string()},
        dir);
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    EXPECT_EQ(r.exitCode, 1) << r.err;
    // One error line, the last (log lines before it, such as the camera.convert = auto
    // decision, are fine).
    const std::vector<std::string> errors = errorLines(r.err);
    ASSERT_EQ(errors.size(), 1u) << r.err;
    EXPECT_EQ(errors[0].rfind("lumar: libcamera: no cameras found (libcamera v", 0), 0u) << r.err;
    EXPECT_EQ(r.err.substr(r.err.size() - errors[0].size() - 1), errors[0] + "\n") << r.err;
    EXPECT_LT(seconds, 10.0);
    EXPECT_FALSE(std::filesystem::exists(dir / "out.png"));
}

} // namespace
} // namespace lumar
