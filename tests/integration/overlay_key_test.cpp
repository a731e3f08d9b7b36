// The key o in `lumar run --preview`'s window, end to end under a private Xvfb: the window as
// the X server holds it shows the headless frame (overlay off), then the setup view over it
// (its status line's box in the top-left corner, the tag's outline and the tracker's search
// windows), then the headless frame again after a second o. Each state is waited for as it
// reaches the screen; nothing is timed.
#include <chrono>
#include <fstream>
#include <functional>
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

bool waitFor(const std::function<bool()>& done, std::chrono::seconds limit)
{
    const auto deadline = std::chrono::steady_clock::now() + limit;
    while (!done()) {
        if (std::chrono::steady_clock::now() > deadline)
            return false;
        std::this_thread::sleep_for(std::chrono::milliseconds(50));
    }
    return true;
}

// One camera image played over and over, a cube on its tag: every frame the same once the
// tag is found.
std::string stillScene()
{
    return "[camera]\nsource = \"images\"\npath = \"frames\"\n"
           "[rendering]\nenvironment_maps = \"off\"\n"
           "[environment]\nmatch_exposure = false\n"
           "[[markers]]\nid = 0\nsize = 0.16\n"
           "[[objects]]\nname = \"cube\"\nmodel = \"builtin:cube\"\nmarker = 0\nsize = 0.08\n";
}

int worstDifference(const std::vector<uint8_t>& a, const std::vector<uint8_t>& b)
{
    if (a.size() != b.size())
        return 256;
    int worst = 0;
    for (size_t i = 0; i < a.size(); ++i)
        worst = std::max(worst, std::abs(int(a[i]) - int(b[i])));
    return worst;
}

// Pixels of the box [x0, x1) x [y0, y1) that differ from the headless frame by more than 8.
int changedIn(const std::vector<uint8_t>& shown, const std::vector<uint8_t>& headless, int x0, int y0, int x1, int y1)
{
    if (shown.size() != headless.size())
        return 0;
    int n = 0;
    for (int y = y0; y < y1; ++y)
        for (int x = x0; x < x1; ++x) {
            const size_t i = (size_t(y) * kWidth + size_t(x)) * 3;
            for (size_t c = 0; c < 3; ++c)
                if (std::abs(int(shown[i + c]) - int(headless[i + c])) > 8) {
                    ++n;
                    break;
                }
        }
    return n;
}

// Pixels turned cyan by the overlay (the search windows' colour, kOverlaySearchWindow blended
// over the picture): red low, green and blue high, where the headless frame was not so.
int cyanAdded(const std::vector<uint8_t>& shown, const std::vector<uint8_t>& headless)
{
    if (shown.size() != headless.size())
        return 0;
    const auto cyan = [](const uint8_t* p) { return p[0] < 90 && p[1] > 150 && p[2] > 170; };
    int n = 0;
    for (size_t i = 0; i + 2 < shown.size(); i += 3)
        n += cyan(&shown[i]) && !cyan(&headless[i]) ? 1 : 0;
    return n;
}

TEST(OverlayKey, TheKeyOTurnsTheSetupViewOnAndOffInThePreviewWindow)
{
    if (std::system("command -v Xvfb >/dev/null 2>&1") != 0)
        GTEST_SKIP() << "Xvfb is not installed (apt-get install xvfb)";
    test::XvfbServer server;
    ASSERT_FALSE(server.display().empty()) << "Xvfb did not start";
    test::X11Viewer viewer(server.display());
    ASSERT_TRUE(viewer.connected());

    const fs::path dir = test::scratchDirectory("overlay-key");
    fs::create_directories(dir / "frames");
    std::ofstream(dir / "camera.toml") << "[camera]\nwidth = " << kWidth << "\nheight = " << kHeight << "\n";
    auto r = test::runLumar({"render", "--config", (dir / "camera.toml").string(), "--frames", "1", "--out",
                             (dir / "frames" / "f.png").string()},
                            dir);
    ASSERT_EQ(r.exitCode, 0) << r.err;
    std::ofstream(dir / "scene.toml") << stillScene();
    r = test::runLumar({"render", "--config", (dir / "scene.toml").string(), "--frames", "5", "--out",
                        (dir / "headless.png").string()},
                       dir);
    ASSERT_EQ(r.exitCode, 0) << r.err;
    const std::vector<uint8_t> headless = readImage(dir / "headless.png", 3).data;

    const fs::path log = dir / "log.txt";
    const pid_t pid = test::spawnLumar({"run", "--config", (dir / "scene.toml").string(), "--preview"}, log,
                                       {"DISPLAY=" + server.display()});
    ASSERT_GT(pid, 0);
    unsigned long window = 0;
    ASSERT_TRUE(waitFor([&] { return (window = viewer.findWindow("lumar")) != 0; }, std::chrono::seconds(60)))
        << test::readText(log);
    std::vector<uint8_t> shown;
    const auto grab = [&] {
        shown = viewer.grab(window, kWidth, kHeight);
        return shown;
    };
    const auto saveShown = [&](const std::string& name) {
        if (shown.size() != headless.size())
            return;
        Image8 image(kWidth, kHeight, 3);
        image.data = shown;
        writePng(dir / name, image);
    };

    // Off: the headless frame, once the tag is found.
    ASSERT_TRUE(waitFor([&] { return worstDifference(grab(), headless) <= 1; }, std::chrono::seconds(60)))
        << test::readText(log);

    // o: the status line's dark box top left, the tag's outline and the search windows.
    viewer.typeKey(window, 'o');
    const bool on = waitFor(
        [&] {
            grab();
            return changedIn(shown, headless, 0, 0, kWidth / 2, 24) > 200 && cyanAdded(shown, headless) > 40;
        },
        std::chrono::seconds(60));
    if (!on)
        saveShown("on.png");
    ASSERT_TRUE(on) << "changed top left " << changedIn(shown, headless, 0, 0, kWidth / 2, 24) << ", cyan "
                    << cyanAdded(shown, headless) << "; see " << (dir / "on.png") << "\n"
                    << test::readText(log);

    // o again: the headless frame once more, bit for bit within the window's ±1.
    viewer.typeKey(window, 'o');
    const bool off = waitFor([&] { return worstDifference(grab(), headless) <= 1; }, std::chrono::seconds(60));
    if (!off)
        saveShown("off.png");
    ASSERT_TRUE(off) << "see " << (dir / "off.png") << "\n" << test::readText(log);

    viewer.requestClose(window);
    int status = 0;
    ASSERT_TRUE(waitFor([&] { return ::waitpid(pid, &status, WNOHANG) == pid; }, std::chrono::seconds(30)))
        << test::readText(log);
    ASSERT_TRUE(WIFEXITED(status)) << test::readText(log);
    EXPECT_EQ(WEXITSTATUS(status), 0) << test::readText(log);
}

} // namespace
} // namespace lumar
