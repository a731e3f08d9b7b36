// `lumar run` under ThreadSanitizer (issue 16): lumar_tsan, the daemon with its render loop,
// reload path, config watcher, signal handlers and threaded classes instrumented
// (tests/tsan/CMakeLists.txt), runs the fake camera with a tag the detection worker finds and
// an object drawn on it, and goes through every kind of reload while frames flow: an edit that
// replaces the tracker (the worker stopped and started again), a SIGHUP storm, an edit that
// adds a model, and a [camera] change (a second camera, capture thread and GL context built
// beside the running ones, then the old ones destroyed). A data race anywhere TSan sees makes
// the daemon exit 66 instead of 0 (TSan's exit code), and its report is in the log.
#include <chrono>
#include <csignal>
#include <fstream>
#include <string>
#include <thread>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <sys/syscall.h>
#include <sys/wait.h>
#include <unistd.h>

#include "run_lumar.h"

namespace lumar {
namespace {

using Clock = std::chrono::steady_clock;

// Replaces a file the way editors do: write a new one beside it, rename it over the old.
void replaceFile(const std::filesystem::path& file, const std::string& text)
{
    const auto partial = file.string() + ".new";
    std::ofstream(partial) << text;
    std::filesystem::rename(partial, file);
}

// A 320x240 fake camera whose tag 0 is tracked and carries the objects; no environment maps
// (the renderer's own time is not what this test is for).
std::string scene(const std::string& camera, const std::string& tracking, const std::string& objects)
{
    return "[camera]\nwidth = 320\nheight = 240\nfps = 30.0\n" + camera +
           "[[markers]]\nid = 0\nsize = 0.16\n"
           "[tracking]\n" +
           tracking + "[rendering]\nenvironment_maps = \"off\"\n" + objects +
           "[output]\npath = \"out.png\"\nstatus_path = \"status.json\"\n";
}

const std::string kSphere = "[[objects]]\nname = \"ball\"\nmodel = \"builtin:sphere\"\nmarker = 0\nsize = 0.1\n";
const std::string kCube = "[[objects]]\nname = \"box\"\nmodel = \"builtin:cube\"\nmarker = 0\n"
                          "offset = [0.1, 0.0, 0.0]\nsize = 0.05\n";

size_t count(const std::string& text, const std::string& what)
{
    size_t found = 0;
    for (size_t at = text.find(what); at != std::string::npos; at = text.find(what, at + 1))
        ++found;
    return found;
}

// The ids of the process' threads now.
std::vector<pid_t> threadsOf(pid_t pid)
{
    std::vector<pid_t> ids;
    for (const auto& entry : std::filesystem::directory_iterator("/proc/" + std::to_string(pid) + "/task"))
        ids.push_back(pid_t(std::stol(entry.path().filename().string())));
    return ids;
}

class RunUnderTsan : public ::testing::Test {
protected:
    void SetUp() override
    {
        dir_ = test::scratchDirectory("tsan-run");
        config_ = dir_ / "scene.toml";
    }
    std::string log() const { return test::readText(dir_ / "log.txt"); }
    // Waits until the log holds `text` `times` times.
    bool waitForLog(const std::string& text, size_t times, std::chrono::seconds limit) const
    {
        const auto deadline = Clock::now() + limit;
        while (count(log(), text) < times)
            if (Clock::now() > deadline)
                return false;
            else
                std::this_thread::sleep_for(std::chrono::milliseconds(50));
        return true;
    }
    // Waits until status.json (rewritten every second) counts more than `after` frames with
    // `objects` objects drawn in the last; returns the frames counted then, 0 on timeout.
    long waitForFrames(long after, int objects, std::chrono::seconds limit) const
    {
        const auto deadline = Clock::now() + limit;
        while (Clock::now() < deadline) {
            const auto json = nlohmann::json::parse(test::readText(dir_ / "status.json"), nullptr, false);
            if (!json.is_discarded() && json.contains("frames") && json["frames"].is_number() &&
                json["frames"].get<long>() > after && json["objects_drawn"] == objects)
                return json["frames"].get<long>();
            std::this_thread::sleep_for(std::chrono::milliseconds(100));
        }
        return 0;
    }

    std::filesystem::path dir_, config_;
};

TEST_F(RunUnderTsan, ReloadsBySignalAndEditWhileFramesFlowReportNoRace)
{
    std::ofstream(config_) << scene("", "", kSphere);
    const pid_t pid = test::spawnLumar({"run", "--config", config_.string()}, dir_ / "log.txt");
    ASSERT_GT(pid, 0);
    // The tag is detected on the worker and the ball drawn on it.
    long frames = waitForFrames(0, 1, std::chrono::seconds(120));
    ASSERT_GT(frames, 0) << log();

    // [tracking] edited: the worker is stopped, the tracker replaced, a new worker started.
    replaceFile(config_, scene("", "quad_decimate = 1.5\n", kSphere));
    ASSERT_TRUE(waitForLog("; new tracker", 1, std::chrono::seconds(60))) << log();
    frames = waitForFrames(frames + 10, 1, std::chrono::seconds(60));
    ASSERT_GT(frames, 0) << "no frames with the object after the new tracker\n" << log();

    // A SIGHUP storm, during frames and during the reloads it causes (each reload of the
    // unchanged file keeps everything). The kernel hands a process's signal to any thread that
    // does not block it, mostly the main one: here each of lumar's threads in turn gets it
    // (the capture thread, the worker, llvmpipe's), so the handler's write and the loop's read
    // are on different threads.
    const std::vector<pid_t> threads = threadsOf(pid);
    ASSERT_GT(threads.size(), 2u);
    for (int i = 0; i < 50; ++i) {
        // A thread may have ended meanwhile (ESRCH): the next one gets the signal.
        ::syscall(SYS_tgkill, pid, threads[size_t(i) % threads.size()], SIGHUP);
        std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
    ASSERT_TRUE(waitForLog("reloaded ", 2, std::chrono::seconds(60))) << log();

    // A second model: the scene changes, camera, context and tracker stay.
    replaceFile(config_, scene("", "quad_decimate = 1.5\n", kSphere + kCube));
    ASSERT_TRUE(waitForLog("models 1 → 2", 1, std::chrono::seconds(60))) << log();
    frames = waitForFrames(frames, 2, std::chrono::seconds(60));
    ASSERT_GT(frames, 0) << log();

    // [camera] changed: a new Pipeline (camera, capture thread, worker, GL context) is built
    // while the old one still exists, then replaces it.
    replaceFile(config_, scene("seed = 7\n", "quad_decimate = 1.5\n", kSphere + kCube));
    ASSERT_TRUE(waitForLog("ms: new camera, GL context", 1, std::chrono::seconds(60))) << log();
    ASSERT_GT(waitForFrames(frames + 10, 2, std::chrono::seconds(60)), 0) << log();

    ASSERT_EQ(::kill(pid, SIGTERM), 0);
    int status = 0;
    ASSERT_EQ(::waitpid(pid, &status, 0), pid);
    const std::string text = log();
    // TSan reports each race as it finds it and makes the exit code 66.
    EXPECT_EQ(count(text, "WARNING: ThreadSanitizer"), 0u) << text;
    ASSERT_TRUE(WIFEXITED(status)) << text;
    EXPECT_EQ(WEXITSTATUS(status), 0) << text;
    EXPECT_NE(text.find("stopped after"), std::string::npos) << text;
}

} // namespace
} // namespace lumar
