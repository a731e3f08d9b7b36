// `lumar run` as a service manager drives it: started, left running, stopped by SIGTERM or
// SIGINT; it must exit 0 with its output complete (every Y4M frame whole).
#include <csignal>
#include <fstream>
#include <thread>

#include <fcntl.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <spawn.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <sys/un.h>
#include <sys/wait.h>

#include "run_lumar.h"

extern char** environ;

namespace lumar {
namespace {

constexpr int kWidth = 320, kHeight = 240;
constexpr size_t kY4mFrameBytes = 6 + size_t(kWidth) * kHeight * 3 / 2; // "FRAME\n" + 4:2:0 planes

size_t fileSize(const std::filesystem::path& p)
{
    std::error_code ec;
    const auto n = std::filesystem::file_size(p, ec);
    return ec ? 0 : size_t(n);
}

class RunCommand : public ::testing::TestWithParam<int> {};

TEST_P(RunCommand, StopsCleanlyOnSignalWithCompleteOutput)
{
    const int signal = GetParam();
    const auto dir = test::scratchDirectory(std::string("run-") + std::to_string(signal));
    const auto video = dir / "live.y4m";
    std::ofstream(dir / "scene.toml") << "[camera]\nwidth = " << kWidth << "\nheight = " << kHeight
                                      << "\n[output]\npath = \"live.y4m\"\n";
    const pid_t pid = test::spawnLumar({"run", "--config", (dir / "scene.toml").string()}, dir / "log.txt");
    ASSERT_GT(pid, 0);

    // Wait for a few frames to be written (the daemon paces itself at 30 fps).
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(60);
    while (fileSize(video) < 5 * kY4mFrameBytes && std::chrono::steady_clock::now() < deadline)
        std::this_thread::sleep_for(std::chrono::milliseconds(50));
    ASSERT_GE(fileSize(video), 5 * kY4mFrameBytes) << test::readText(dir / "log.txt");

    ASSERT_EQ(::kill(pid, signal), 0);
    int status = 0;
    ASSERT_EQ(::waitpid(pid, &status, 0), pid);
    const std::string log = test::readText(dir / "log.txt");
    ASSERT_TRUE(WIFEXITED(status)) << "killed by a signal instead of stopping\n" << log;
    EXPECT_EQ(WEXITSTATUS(status), 0) << log;
    EXPECT_NE(log.find("stopped after"), std::string::npos) << log;

    // Header line plus whole frames only.
    const std::string bytes = test::readText(video);
    const size_t header = bytes.find('\n') + 1;
    ASSERT_GT(header, 1u);
    EXPECT_EQ((bytes.size() - header) % kY4mFrameBytes, 0u) << "a frame was cut short";
}

INSTANTIATE_TEST_SUITE_P(Signals, RunCommand, ::testing::Values(SIGTERM, SIGINT));

// Replaces a file the way editors do: write a new one beside it, rename it over the old.
void replaceFile(const std::filesystem::path& file, const std::string& text)
{
    const auto partial = file.string() + ".new";
    std::ofstream(partial) << text;
    std::filesystem::rename(partial, file);
}

// `cameraExtra` and `rest` are added to [camera] and after [output].
std::string sceneWritingTo(const std::string& video, const std::string& cameraExtra = "", const std::string& rest = "")
{
    return "[camera]\nwidth = " + std::to_string(kWidth) + "\nheight = " + std::to_string(kHeight) + "\n" +
           cameraExtra + "[output]\npath = \"" + video + "\"\nstatus_path = \"status.json\"\n" + rest;
}

// Waits until the log holds `text` (`count` times); false after `limit`.
bool waitForLog(const std::filesystem::path& log, const std::string& text, size_t count, std::chrono::seconds limit)
{
    const auto deadline = std::chrono::steady_clock::now() + limit;
    for (;;) {
        const std::string s = test::readText(log);
        size_t found = 0;
        for (size_t at = s.find(text); at != std::string::npos; at = s.find(text, at + 1))
            ++found;
        if (found >= count)
            return true;
        if (std::chrono::steady_clock::now() > deadline)
            return false;
        std::this_thread::sleep_for(std::chrono::milliseconds(50));
    }
}

bool waitForFrames(const std::filesystem::path& video, size_t frames, std::chrono::seconds limit)
{
    const auto deadline = std::chrono::steady_clock::now() + limit;
    while (fileSize(video) < frames * kY4mFrameBytes) {
        if (std::chrono::steady_clock::now() > deadline)
            return false;
        std::this_thread::sleep_for(std::chrono::milliseconds(50));
    }
    return true;
}

TEST(RunReload, EditsApplyAndABadFileKeepsTheLastGoodConfiguration)
{
    const auto dir = test::scratchDirectory("run-reload");
    const auto config = dir / "scene.toml";
    std::ofstream(config) << sceneWritingTo("a.y4m");
    // The unit runs lumar with UMask=0077: the status file must stay readable by others.
    const mode_t previousMask = ::umask(077);
    const pid_t pid = test::spawnLumar({"run", "--config", config.string()}, dir / "log.txt");
    ::umask(previousMask);
    ASSERT_GT(pid, 0);
    ASSERT_TRUE(waitForFrames(dir / "a.y4m", 3, std::chrono::seconds(60))) << test::readText(dir / "log.txt");

    // An edit on disk (rename over the file) is picked up by the watch. The camera is the
    // same, so it and the GL context are kept.
    replaceFile(config, sceneWritingTo("b.y4m"));
    ASSERT_TRUE(waitForFrames(dir / "b.y4m", 3, std::chrono::seconds(60))) << test::readText(dir / "log.txt");
    EXPECT_TRUE(waitForLog(dir / "log.txt", "ms: kept camera, GL context", 1, std::chrono::seconds(10)))
        << test::readText(dir / "log.txt");

    // A broken file is rejected with its line; the running configuration goes on.
    replaceFile(config, "[camera]\nwidth = \"wide\"\n");
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(30);
    while (test::readText(dir / "log.txt").find("configuration rejected") == std::string::npos &&
           std::chrono::steady_clock::now() < deadline)
        std::this_thread::sleep_for(std::chrono::milliseconds(50));
    const std::string log = test::readText(dir / "log.txt");
    EXPECT_NE(log.find("configuration rejected"), std::string::npos) << log;
    EXPECT_NE(log.find("scene.toml:2: camera.width"), std::string::npos) << log;
    std::this_thread::sleep_for(std::chrono::milliseconds(1200));
    const auto rejected = nlohmann::json::parse(test::readText(dir / "status.json"));
    EXPECT_EQ(rejected["config"].get<std::string>().rfind("rejected: ", 0), 0u) << rejected.dump();
    const size_t before = fileSize(dir / "b.y4m");
    EXPECT_TRUE(waitForFrames(dir / "b.y4m", before / kY4mFrameBytes + 3, std::chrono::seconds(30)))
        << "frames keep flowing after a rejected file";

    // SIGHUP reloads too (the file is rewritten in place first, without an event in between
    // being required). A [camera] change takes a new camera and GL context.
    replaceFile(config, sceneWritingTo("c.y4m", "seed = 7\n"));
    ::kill(pid, SIGHUP);
    EXPECT_TRUE(waitForFrames(dir / "c.y4m", 3, std::chrono::seconds(60))) << test::readText(dir / "log.txt");
    EXPECT_TRUE(waitForLog(dir / "log.txt", "ms: new camera, GL context", 1, std::chrono::seconds(10)))
        << test::readText(dir / "log.txt");

    // The status file reports the rejected file until a good one is accepted (it is
    // rewritten every second).
    std::this_thread::sleep_for(std::chrono::milliseconds(1200));
    const auto json = nlohmann::json::parse(test::readText(dir / "status.json"));
    EXPECT_EQ(json["config"], "ok") << json.dump();
    EXPECT_EQ(json["camera"], "ok") << json.dump();
    EXPECT_GT(json["frames"].get<long>(), 0);
    EXPECT_GT(json["startup_ms"].get<double>(), 0.0) << json.dump();
    EXPECT_GT(json["last_reload_ms"].get<double>(), 0.0) << json.dump();
    const auto perms = std::filesystem::status(dir / "status.json").permissions();
    EXPECT_NE(perms & std::filesystem::perms::others_read, std::filesystem::perms::none)
        << "status.json not world-readable";
    EXPECT_GT(json["fps"].get<double>(), 0.0);

    ASSERT_EQ(::kill(pid, SIGTERM), 0);
    int status = 0;
    ASSERT_EQ(::waitpid(pid, &status, 0), pid);
    EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << test::readText(dir / "log.txt");
}

// A phantom whose mesh file is broken is rejected like any bad file, naming the file, line
// and key; the running scene (with its good phantom) goes on.
TEST(RunReload, ABrokenPhantomMeshKeepsTheLastGoodConfiguration)
{
    const auto dir = test::scratchDirectory("run-reload-phantom");
    const auto config = dir / "scene.toml";
    const auto withPhantom = [](const std::string& model) {
        return "[[markers]]\nid = 0\nsize = 0.16\n[[phantoms]]\nmarker = 0\nshape = \"mesh\"\nmodel = \"" + model +
               "\"\nsize = 0.1\n";
    };
    std::ofstream(config) << sceneWritingTo("a.y4m", "", withPhantom("builtin:cube"));
    std::ofstream(dir / "broken.glb") << "glTF, but not really";
    const pid_t pid = test::spawnLumar({"run", "--config", config.string()}, dir / "log.txt");
    ASSERT_GT(pid, 0);
    ASSERT_TRUE(waitForFrames(dir / "a.y4m", 3, std::chrono::seconds(60))) << test::readText(dir / "log.txt");

    replaceFile(config, sceneWritingTo("a.y4m", "", withPhantom("broken.glb")));
    EXPECT_TRUE(waitForLog(dir / "log.txt", "configuration rejected", 1, std::chrono::seconds(30)))
        << test::readText(dir / "log.txt");
    const std::string log = test::readText(dir / "log.txt");
    EXPECT_NE(log.find("phantoms[0].model: " + (dir / "broken.glb").string()), std::string::npos) << log;
    const size_t before = fileSize(dir / "a.y4m");
    EXPECT_TRUE(waitForFrames(dir / "a.y4m", before / kY4mFrameBytes + 3, std::chrono::seconds(30)))
        << "frames keep flowing after a rejected file";

    ASSERT_EQ(::kill(pid, SIGTERM), 0);
    int status = 0;
    ASSERT_EQ(::waitpid(pid, &status, 0), pid);
    EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << test::readText(dir / "log.txt");
}

// Waits until status.json says `key` = `value`; the last status read.
nlohmann::json waitForStatus(const std::filesystem::path& file, const std::string& key, int value,
                             std::chrono::seconds limit)
{
    const auto deadline = std::chrono::steady_clock::now() + limit;
    nlohmann::json json;
    while (std::chrono::steady_clock::now() < deadline) {
        json = nlohmann::json::parse(test::readText(file), nullptr, false);
        if (!json.is_discarded() && json.contains(key) && json[key] == value)
            break;
        std::this_thread::sleep_for(std::chrono::milliseconds(100));
    }
    return json;
}

TEST(RunReload, AModelChangeKeepsTheCameraAndGlContextAndShowsTheNewScene)
{
    const auto dir = test::scratchDirectory("run-reload-models");
    const auto config = dir / "scene.toml";
    const std::string marker = "[[markers]]\nid = 0\nsize = 0.16\n[rendering]\nenvironment_maps = \"off\"\n";
    const std::string sphere = "[[objects]]\nname = \"ball\"\nmodel = \"builtin:sphere\"\nmarker = 0\nsize = 0.1\n";
    const std::string cube = "[[objects]]\nname = \"box\"\nmodel = \"builtin:cube\"\nmarker = 0\n"
                             "offset = [0.1, 0.0, 0.0]\nsize = 0.05\n";
    std::ofstream(config) << sceneWritingTo("a.y4m", "", marker + sphere);
    const pid_t pid = test::spawnLumar({"run", "--config", config.string()}, dir / "log.txt");
    ASSERT_GT(pid, 0);
    auto json = waitForStatus(dir / "status.json", "objects_drawn", 1, std::chrono::seconds(60));
    ASSERT_EQ(json["objects_drawn"], 1) << json.dump() << test::readText(dir / "log.txt");
    EXPECT_GT(json["startup_ms"].get<double>(), 0.0) << json.dump();
    EXPECT_TRUE(json["last_reload_ms"].is_null()) << json.dump();

    // A second object: the scene changes, the camera and the GL context stay.
    replaceFile(config, sceneWritingTo("a.y4m", "", marker + sphere + cube));
    EXPECT_TRUE(waitForLog(dir / "log.txt", "ms: kept camera, GL context, tracker, environment map; models 1 → 2", 1,
                           std::chrono::seconds(30)))
        << test::readText(dir / "log.txt");
    json = waitForStatus(dir / "status.json", "objects_drawn", 2, std::chrono::seconds(30));
    EXPECT_EQ(json["objects_drawn"], 2) << json.dump() << test::readText(dir / "log.txt");
    EXPECT_GT(json["last_reload_ms"].get<double>(), 0.0) << json.dump();

    ASSERT_EQ(::kill(pid, SIGTERM), 0);
    int status = 0;
    ASSERT_EQ(::waitpid(pid, &status, 0), pid);
    EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << test::readText(dir / "log.txt");
    // The recording went on through the reload: whole frames, one stream.
    const std::string bytes = test::readText(dir / "a.y4m");
    const size_t header = bytes.find('\n') + 1;
    EXPECT_EQ((bytes.size() - header) % kY4mFrameBytes, 0u);
    EXPECT_EQ(bytes.find("YUV4MPEG2", 1), std::string::npos) << "the recording was restarted";
}

// The systemd notify protocol against a datagram socket standing in for systemd.
TEST(RunNotify, ReadyAfterTheFirstFrameThenWatchdogAndStatus)
{
    const auto dir = test::scratchDirectory("run-notify");
    const auto socketPath = dir / "notify.sock";
    const int sock = ::socket(AF_UNIX, SOCK_DGRAM | SOCK_CLOEXEC, 0);
    ASSERT_GE(sock, 0);
    sockaddr_un address{};
    address.sun_family = AF_UNIX;
    std::snprintf(address.sun_path, sizeof address.sun_path, "%s", socketPath.c_str());
    ASSERT_EQ(::bind(sock, reinterpret_cast<const sockaddr*>(&address), sizeof address), 0);
    timeval timeout{1, 0};
    ::setsockopt(sock, SOL_SOCKET, SO_RCVTIMEO, &timeout, sizeof timeout);

    std::ofstream(dir / "scene.toml") << sceneWritingTo("live.y4m");
    const pid_t pid = test::spawnLumar({"run", "--config", (dir / "scene.toml").string()}, dir / "log.txt",
                                       {"NOTIFY_SOCKET=" + socketPath.string(), "WATCHDOG_USEC=200000"});
    ASSERT_GT(pid, 0);

    std::vector<std::string> messages;
    auto has = [&](const std::string& prefix) {
        for (const auto& m : messages)
            if (m.rfind(prefix, 0) == 0)
                return true;
        return false;
    };
    auto hasFpsStatus = [&] {
        for (const auto& m : messages)
            if (m.rfind("STATUS=", 0) == 0 && m.find("fps") != std::string::npos)
                return true;
        return false;
    };
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(60);
    while (!(has("READY=1") && hasFpsStatus() && has("WATCHDOG=1")) && std::chrono::steady_clock::now() < deadline) {
        char buffer[512];
        const ssize_t n = ::recv(sock, buffer, sizeof buffer - 1, 0);
        if (n > 0)
            messages.emplace_back(buffer, size_t(n));
    }
    ::kill(pid, SIGTERM);
    int status = 0;
    ::waitpid(pid, &status, 0);
    ::close(sock);

    ASSERT_TRUE(has("READY=1")) << test::readText(dir / "log.txt");
    EXPECT_TRUE(has("WATCHDOG=1"));
    // A status from the first frame on (start-up time), then the frame rate every 5 s.
    ASSERT_TRUE(has("STATUS=first frame presented after "));
    EXPECT_TRUE(hasFpsStatus());
    // READY comes after the first frame exists.
    EXPECT_GT(fileSize(dir / "live.y4m"), kY4mFrameBytes);
    for (const auto& m : messages) {
        if (m.rfind("STATUS=", 0) == 0 && m.rfind("STATUS=first frame", 0) != 0) {
            EXPECT_NE(m.find("fps"), std::string::npos) << m;
        }
    }
}

TEST(RunCommandInput, BadConfigExitsTwoWithoutStarting)
{
    const auto dir = test::scratchDirectory("run-bad");
    std::ofstream(dir / "scene.toml") << "[camera]\nfps = -3\n";
    const auto r = test::runLumar({"run", "--config", (dir / "scene.toml").string()}, dir);
    EXPECT_EQ(r.exitCode, 2);
    EXPECT_NE(r.err.find("scene.toml:2: camera.fps"), std::string::npos) << r.err;
}

} // namespace
} // namespace lumar
