// `lumar run --preview` under a private Xvfb, looked at from outside as a user sees it: the
// window the X server holds shows the frame `lumar render` writes for the same scene (+-1),
// a reload keeps that window, closing it ends the run with exit 0; without a display server
// the run says so in one line and writes the headless output instead.
#include <fstream>
#include <thread>

#include <gtest/gtest.h>
#include <sys/wait.h>

#include "gl/x11_viewer.h"
#include "gl/xvfb_server.h"
#include "output/frame_writer.h"
#include "run_lumar.h"

namespace lumar {
namespace {

namespace fs = std::filesystem;

constexpr int kWidth = 320, kHeight = 240;

int countOf(const std::string& text, const std::string& what)
{
    int n = 0;
    for (size_t at = text.find(what); at != std::string::npos; at = text.find(what, at + 1))
        ++n;
    return n;
}

TEST(WindowRun, TheWindowShowsTheHeadlessFrameKeepsItOnReloadAndClosingEndsTheRun)
{
    if (!test::XvfbServer::installed())
        GTEST_SKIP() << "Xvfb is not installed (apt-get install xvfb)";
    test::XvfbServer server;
    ASSERT_FALSE(server.display().empty()) << "Xvfb did not start";
    test::X11Viewer viewer(server.display());
    ASSERT_TRUE(viewer.connected());

    const fs::path dir = test::scratchDirectory("window-run");
    const auto r = test::prepareStillScene(dir, kWidth, kHeight, test::stillScene());
    ASSERT_EQ(r.exitCode, 0) << r.err;
    const Image8 headless = readImage(dir / "headless.png", 3);

    const fs::path log = dir / "log.txt";
    const pid_t pid = test::spawnLumar({"run", "--config", (dir / "scene.toml").string(), "--preview"}, log,
                                       {"DISPLAY=" + server.display()});
    ASSERT_GT(pid, 0);
    unsigned long window = 0;
    ASSERT_TRUE(test::waitUntil([&] { return (window = viewer.findWindow("lumar")) != 0; }, std::chrono::seconds(60)))
        << test::readText(log);
    // The detection worker finds the tag within a few frames; from then on every frame is
    // the same. Compare until one matches (a slow machine may take a while to get there).
    int worst = 255;
    Image8 shownImage(kWidth, kHeight, 3);
    test::waitUntil(
        [&] {
            const std::vector<uint8_t> shown = viewer.grab(window, kWidth, kHeight);
            if (shown.size() == shownImage.data.size())
                shownImage.data = shown;
            if (shown.size() != headless.data.size())
                return false;
            worst = 0;
            for (size_t i = 0; i < shown.size(); ++i)
                worst = std::max(worst, std::abs(int(shown[i]) - int(headless.data[i])));
            return worst <= 1;
        },
        std::chrono::seconds(30));
    if (worst > 1)
        writePng(dir / "shown.png", shownImage); // beside headless.png, to look at
    EXPECT_LE(worst, 1) << "see " << (dir / "shown.png") << "\n" << test::readText(log);

    // A reload keeps the window.
    {
        const fs::path partial = dir / "scene.toml.new";
        std::ofstream(partial) << test::stillScene("[tracking]\nfilter = false\n");
        fs::rename(partial, dir / "scene.toml");
    }
    ASSERT_TRUE(
        test::waitUntil([&] { return countOf(test::readText(log), "reloaded") >= 1; }, std::chrono::seconds(60)))
        << test::readText(log);
    EXPECT_EQ(viewer.findWindow("lumar"), window);

    viewer.requestClose(window);
    int status = 0;
    ASSERT_TRUE(test::waitUntil([&] { return ::waitpid(pid, &status, WNOHANG) == pid; }, std::chrono::seconds(30)))
        << test::readText(log);
    const std::string text = test::readText(log);
    ASSERT_TRUE(WIFEXITED(status)) << text;
    EXPECT_EQ(WEXITSTATUS(status), 0) << text;
    EXPECT_NE(text.find("the preview window was closed"), std::string::npos) << text;
}

TEST(WindowRun, WithoutADisplayServerItSaysSoOnceAndWritesTheHeadlessOutput)
{
    const fs::path dir = test::scratchDirectory("window-none");
    std::ofstream(dir / "scene.toml") << "[camera]\nwidth = " << kWidth << "\nheight = " << kHeight
                                      << "\n[output]\nsink = \"window\"\npath = \"out.png\"\n";
    const auto r = test::runLumar({"run", "--config", (dir / "scene.toml").string(), "--frames", "3"}, dir,
                                  {"DISPLAY=", "WAYLAND_DISPLAY="});
    EXPECT_EQ(r.exitCode, 0) << r.err;
    EXPECT_EQ(countOf(r.err, "no display server"), 1) << r.err;
    EXPECT_NE(r.err.find("falling back to the headless sink"), std::string::npos) << r.err;
    EXPECT_TRUE(fs::exists(dir / "out.png"));
}

TEST(WindowRun, ADisplayThatGoesAwayEndsTheRunWithOneLine)
{
    if (!test::XvfbServer::installed())
        GTEST_SKIP() << "Xvfb is not installed (apt-get install xvfb)";
    test::XvfbServer server;
    ASSERT_FALSE(server.display().empty());
    test::X11Viewer viewer(server.display());
    ASSERT_TRUE(viewer.connected());
    const fs::path dir = test::scratchDirectory("window-lost");
    std::ofstream(dir / "scene.toml") << "[camera]\nwidth = " << kWidth << "\nheight = " << kHeight << "\n";
    const fs::path log = dir / "log.txt";
    const pid_t pid = test::spawnLumar({"run", "--config", (dir / "scene.toml").string(), "--preview"}, log,
                                       {"DISPLAY=" + server.display()});
    ASSERT_GT(pid, 0);
    // The display goes away while lumar runs, once its window and EGL surface are made (Mesa's
    // EGL crashes when the server dies inside eglCreateWindowSurface: not a case this covers).
    ASSERT_TRUE(test::waitUntil([&] { return viewer.findWindow("lumar") != 0; }, std::chrono::seconds(60)))
        << test::readText(log);
    ASSERT_TRUE(test::waitUntil([&] { return test::readText(log).find("preview window ") != std::string::npos; },
                                std::chrono::seconds(60)))
        << test::readText(log);
    std::this_thread::sleep_for(std::chrono::milliseconds(300));
    viewer.close();
    server.stop();
    int status = 0;
    ASSERT_TRUE(test::waitUntil([&] { return ::waitpid(pid, &status, WNOHANG) == pid; }, std::chrono::seconds(30)));
    const std::string text = test::readText(log);
    ASSERT_TRUE(WIFEXITED(status)) << "crashed\n" << text;
    EXPECT_EQ(WEXITSTATUS(status), 1) << text;
    EXPECT_NE(text.find("lumar: "), std::string::npos) << text;
}

} // namespace
} // namespace lumar
