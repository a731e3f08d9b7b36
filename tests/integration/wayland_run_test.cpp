// `lumar run --preview` on a Wayland session (WAYLAND_DISPLAY set, no X server) under a private
// headless weston: the preview is a Wayland window, frames are shown there and the run ends
// with exit 0; a WAYLAND_DISPLAY that names no compositor says so in one line and falls back
// to the headless sink; a compositor that goes away ends the run with one line. Skips without
// weston.
#include <fstream>

#include <gtest/gtest.h>
#include <sys/wait.h>

#include "gl/weston_server.h"
#include "run_lumar.h"

namespace lumar {
namespace {

namespace fs = std::filesystem;

int countOf(const std::string& text, const std::string& what)
{
    int n = 0;
    for (size_t at = text.find(what); at != std::string::npos; at = text.find(what, at + 1))
        ++n;
    return n;
}

TEST(WaylandRun, ThePreviewIsAWaylandWindowOnAWaylandSession)
{
    if (!test::WestonServer::installed())
        GTEST_SKIP() << "weston is not installed (apt-get install weston)";
    test::WestonServer server;
    if (server.socket().empty())
        GTEST_SKIP() << "weston did not start on its headless backend";
    const fs::path dir = test::scratchDirectory("wayland-run");
    std::ofstream(dir / "scene.toml") << "[camera]\nwidth = 320\nheight = 240\n[output]\noverlay = true\n";
    const auto r =
        test::runLumar({"run", "--config", (dir / "scene.toml").string(), "--preview", "--frames", "10"}, dir,
                       {"DISPLAY=", "WAYLAND_DISPLAY=" + server.name(), "XDG_RUNTIME_DIR=" + server.runtimeDir()});
    EXPECT_EQ(r.exitCode, 0) << r.err;
    EXPECT_NE(r.err.find("on Wayland display " + server.name()), std::string::npos) << r.err;
    EXPECT_EQ(countOf(r.err, "no display server"), 0) << r.err;
}

TEST(WaylandRun, ACompositorThatGoesAwayEndsTheRunWithOneLine)
{
    if (!test::WestonServer::installed())
        GTEST_SKIP() << "weston is not installed (apt-get install weston)";
    test::WestonServer server;
    if (server.socket().empty())
        GTEST_SKIP() << "weston did not start on its headless backend";
    const fs::path dir = test::scratchDirectory("wayland-lost");
    std::ofstream(dir / "scene.toml") << "[camera]\nwidth = 320\nheight = 240\n";
    const fs::path log = dir / "log.txt";
    const pid_t pid =
        test::spawnLumar({"run", "--config", (dir / "scene.toml").string(), "--preview"}, log,
                         {"DISPLAY=", "WAYLAND_DISPLAY=" + server.name(), "XDG_RUNTIME_DIR=" + server.runtimeDir()});
    ASSERT_GT(pid, 0);
    ASSERT_TRUE(test::waitUntil([&] { return test::readText(log).find("first frame presented") != std::string::npos; },
                                std::chrono::seconds(60)))
        << test::readText(log);
    server.stop();
    int status = 0;
    ASSERT_TRUE(test::waitUntil([&] { return ::waitpid(pid, &status, WNOHANG) == pid; }, std::chrono::seconds(30)))
        << test::readText(log);
    const std::string text = test::readText(log);
    ASSERT_TRUE(WIFEXITED(status)) << "crashed\n" << text;
    EXPECT_EQ(WEXITSTATUS(status), 1) << text;
    EXPECT_EQ(countOf(text, "lumar: "), 1) << text;
}

TEST(WaylandRun, AWaylandDisplayThatIsNotThereFallsBackInOneLine)
{
    const fs::path dir = test::scratchDirectory("wayland-none");
    std::ofstream(dir / "scene.toml") << "[camera]\nwidth = 320\nheight = 240\n[output]\nsink = \"window\"\npath = "
                                         "\"out.png\"\n";
    const auto r =
        test::runLumar({"run", "--config", (dir / "scene.toml").string(), "--frames", "3"}, dir,
                       {"DISPLAY=", "WAYLAND_DISPLAY=wayland-lumar-nowhere", "XDG_RUNTIME_DIR=" + dir.string()});
    EXPECT_EQ(r.exitCode, 0) << r.err;
    EXPECT_EQ(countOf(r.err, "no display server"), 1) << r.err;
    EXPECT_NE(r.err.find("wayland-lumar-nowhere"), std::string::npos) << r.err;
    EXPECT_TRUE(fs::exists(dir / "out.png"));
}

} // namespace
} // namespace lumar
