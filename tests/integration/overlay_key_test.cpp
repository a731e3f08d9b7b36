// The keys of `lumar run --preview`'s window, end to end under a private Xvfb, on X11 (lumar's
// own X window) and on Wayland (a weston on its X11 backend inside the same Xvfb, its kiosk
// shell showing lumar's window full-output and undecorated, so weston's X window holds exactly
// the frame weston composited from lumar's buffer). Either way the frame is read back from the
// X server, never from lumar: it shows the headless frame (overlay off, +-1), then after the key
// o the setup view over it (its status line's box in the top-left corner, the tag's outline and
// the tracker's search windows), then the headless frame again after a second o. The run then
// ends with exit 0: on X11 by the window manager's close request; on Wayland by the key q,
// since weston 10's shells have no way to send a toplevel its close request. Each state is
// waited for as it reaches the screen; nothing is timed.
#include <chrono>
#include <fstream>
#include <memory>
#include <thread>

#include <gtest/gtest.h>
#include <sys/wait.h>

#include "gl/weston_server.h"
#include "gl/x11_viewer.h"
#include "gl/xvfb_server.h"
#include "output/frame_writer.h"
#include "run_lumar.h"

namespace lumar {
namespace {

namespace fs = std::filesystem;

constexpr int kWidth = 320, kHeight = 240;

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

enum class Session { X11, Wayland };

class OverlayKey : public ::testing::TestWithParam<Session> {};

TEST_P(OverlayKey, TheKeyOTurnsTheSetupViewOnAndOffInThePreviewWindow)
{
    const bool wayland = GetParam() == Session::Wayland;
    if (!test::XvfbServer::installed())
        GTEST_SKIP() << "Xvfb is not installed (apt-get install xvfb)";
    if (wayland && !test::WestonServer::installed())
        GTEST_SKIP() << "weston is not installed (apt-get install weston)";
    test::XvfbServer server;
    ASSERT_FALSE(server.display().empty()) << "Xvfb did not start";
    test::X11Viewer viewer(server.display());
    ASSERT_TRUE(viewer.connected());
    // On Wayland, weston's output is the frame's size: the kiosk shell's full-output toplevel
    // is then lumar's frame exactly, at the X window's origin.
    std::unique_ptr<test::WestonServer> weston;
    std::vector<std::string> environment{"DISPLAY=" + server.display()};
    if (wayland) {
        weston = std::make_unique<test::WestonServer>(kWidth, kHeight, server.display());
        ASSERT_FALSE(weston->socket().empty()) << "weston did not start on its X11 backend";
        environment = {"DISPLAY=", "WAYLAND_DISPLAY=" + weston->name(), "XDG_RUNTIME_DIR=" + weston->runtimeDir()};
    }

    const fs::path dir = test::scratchDirectory(wayland ? "overlay-key-wayland" : "overlay-key");
    const auto r = test::prepareStillScene(dir, kWidth, kHeight, test::stillScene());
    ASSERT_EQ(r.exitCode, 0) << r.err;
    const std::vector<uint8_t> headless = readImage(dir / "headless.png", 3).data;

    const fs::path log = dir / "log.txt";
    const pid_t pid =
        test::spawnLumar({"run", "--config", (dir / "scene.toml").string(), "--preview"}, log, environment);
    ASSERT_GT(pid, 0);
    const std::string title = wayland ? test::WestonServer::x11WindowTitle() : "lumar";
    unsigned long window = 0;
    ASSERT_TRUE(test::waitUntil([&] { return (window = viewer.findWindow(title)) != 0; }, std::chrono::seconds(60)))
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
    const bool first =
        test::waitUntil([&] { return worstDifference(grab(), headless) <= 1; }, std::chrono::seconds(60));
    if (!first)
        saveShown("first.png");
    ASSERT_TRUE(first) << "worst difference " << worstDifference(shown, headless) << "; see " << (dir / "first.png")
                       << "\n"
                       << test::readText(log);
    if (wayland) {
        EXPECT_NE(test::readText(log).find("on Wayland display " + weston->name()), std::string::npos)
            << test::readText(log);
    }

    // o: the status line's dark box top left, the tag's outline and the search windows.
    viewer.typeKey(window, 'o');
    const bool on = test::waitUntil(
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

    // o again: the headless frame once more, bit for bit within the window's +-1.
    viewer.typeKey(window, 'o');
    const bool off = test::waitUntil([&] { return worstDifference(grab(), headless) <= 1; }, std::chrono::seconds(60));
    if (!off)
        saveShown("off.png");
    ASSERT_TRUE(off) << "see " << (dir / "off.png") << "\n" << test::readText(log);

    if (wayland)
        viewer.typeKey(window, 'q');
    else
        viewer.requestClose(window);
    int status = 0;
    ASSERT_TRUE(test::waitUntil([&] { return ::waitpid(pid, &status, WNOHANG) == pid; }, std::chrono::seconds(30)))
        << test::readText(log);
    ASSERT_TRUE(WIFEXITED(status)) << test::readText(log);
    EXPECT_EQ(WEXITSTATUS(status), 0) << test::readText(log);
}

INSTANTIATE_TEST_SUITE_P(Sessions, OverlayKey, ::testing::Values(Session::X11, Session::Wayland),
                         [](const ::testing::TestParamInfo<Session>& param) {
                             return param.param == Session::X11 ? std::string("X11") : std::string("Wayland");
                         });

} // namespace
} // namespace lumar
