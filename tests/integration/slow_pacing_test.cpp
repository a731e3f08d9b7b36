// Issue 16: a slow frame rate must not make `lumar run` deaf to the service manager. A Y4M
// clip at 0.1 fps (its own header's rate) and the fake camera at 0.02 fps leave the loop
// waiting 10 s and 50 s for the next frame; SIGTERM or SIGINT in that wait must end it with
// exit 0 and the usual "stopped after N frames", long before the next frame is due (systemd
// would otherwise end the stop with SIGKILL).
#include <chrono>
#include <csignal>
#include <fstream>
#include <string>
#include <thread>

#include <gtest/gtest.h>
#include <sys/wait.h>

#include "run_lumar.h"

namespace lumar {
namespace {

using Clock = std::chrono::steady_clock;

bool logHas(const std::filesystem::path& log, const std::string& text, std::chrono::seconds limit)
{
    const auto deadline = Clock::now() + limit;
    while (test::readText(log).find(text) == std::string::npos) {
        if (Clock::now() > deadline)
            return false;
        std::this_thread::sleep_for(std::chrono::milliseconds(50));
    }
    return true;
}

// Writes a 64x48 4:2:0 clip of `frames` grey frames at `rate` ("1:10" = 0.1 fps).
void writeClip(const std::filesystem::path& file, const std::string& rate, int frames)
{
    std::ofstream out(file, std::ios::binary);
    out << "YUV4MPEG2 W64 H48 F" << rate << " Ip A1:1 C420jpeg\n";
    const std::string planes(64 * 48 * 3 / 2, char(128));
    for (int i = 0; i < frames; ++i)
        out << "FRAME\n" << planes;
}

struct Source {
    const char* name;
    double frameIntervalS; // what the loop waits for the next frame
    std::string camera;    // the [camera] table's body
};

class SlowPacing : public ::testing::TestWithParam<std::tuple<int, int>> {};

const Source& sourceAt(int index)
{
    static const Source kSources[] = {
        {"y4m", 10.0, "source = \"y4m\"\npath = \"slow.y4m\"\nloop = true\n"},
        {"fake", 50.0, "width = 160\nheight = 120\nfps = 0.02\n"},
    };
    return kSources[index];
}

TEST_P(SlowPacing, AStopSignalEndsTheWaitForTheNextFrame)
{
    const auto [signal, sourceIndex] = GetParam();
    const Source& source = sourceAt(sourceIndex);
    const auto dir = test::scratchDirectory(std::string("slow-") + source.name + "-" + std::to_string(signal));
    writeClip(dir / "slow.y4m", "1:10", 3);
    std::ofstream(dir / "scene.toml") << "[camera]\n"
                                      << source.camera
                                      << "[output]\npath = \"out.png\"\nstatus_path = \"status.json\"\n";
    const pid_t pid = test::spawnLumar({"run", "--config", (dir / "scene.toml").string()}, dir / "log.txt");
    ASSERT_GT(pid, 0);

    // The first frame is shown at once; the second is due a whole frame interval later.
    ASSERT_TRUE(logHas(dir / "log.txt", "first frame presented", std::chrono::seconds(120)))
        << test::readText(dir / "log.txt");
    std::this_thread::sleep_for(std::chrono::milliseconds(300)); // well inside the wait
    const auto sent = Clock::now();
    ASSERT_EQ(::kill(pid, signal), 0);
    int status = 0;
    ASSERT_EQ(::waitpid(pid, &status, 0), pid);
    const double tookS = std::chrono::duration<double>(Clock::now() - sent).count();
    const std::string log = test::readText(dir / "log.txt");
    ASSERT_TRUE(WIFEXITED(status)) << "killed by a signal instead of stopping\n" << log;
    EXPECT_EQ(WEXITSTATUS(status), 0) << log;
    EXPECT_NE(log.find("stopped after 1 frames"), std::string::npos) << log;
    // Not a timing assertion: the bound is half the interval the loop was waiting out, so it
    // tells "answered the signal" from "slept until the next frame" on any load. The daemon's
    // own answer is one 20 ms pacing slice (strace: the stop line 41 ms after SIGTERM, exit
    // 0.48 s after it, at load 20); the figure is printed for the notes.
    EXPECT_LT(tookS, source.frameIntervalS / 2) << log;
    std::printf("%s, signal %d: exited %.3f s after the signal\n", source.name, signal, tookS);
}

INSTANTIATE_TEST_SUITE_P(Signals, SlowPacing,
                         ::testing::Combine(::testing::Values(SIGTERM, SIGINT), ::testing::Values(0, 1)),
                         [](const auto& param) {
                             return std::string(std::get<0>(param.param) == SIGTERM ? "Sigterm" : "Sigint") +
                                    (std::get<1>(param.param) == 0 ? "Y4mAtPoint1Fps" : "FakeCameraAtPoint02Fps");
                         });

} // namespace
} // namespace lumar
