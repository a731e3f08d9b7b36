// `lumar run` as a service manager drives it: started, left running, stopped by SIGTERM or
// SIGINT; it must exit 0 with its output complete (every Y4M frame whole).
#include <csignal>
#include <fcntl.h>
#include <fstream>
#include <spawn.h>
#include <sys/wait.h>
#include <thread>

#include <gtest/gtest.h>

#include "run_lumar.h"

extern char** environ;

namespace lumar {
namespace {

constexpr int kWidth = 320, kHeight = 240;
constexpr size_t kY4mFrameBytes = 6 + size_t(kWidth) * kHeight * 3 / 2;  // "FRAME\n" + 4:2:0 planes

// Starts lumar with stdout/stderr redirected to files; returns its pid.
pid_t spawnLumar(const std::vector<std::string>& args, const std::filesystem::path& log)
{
    std::vector<std::string> argv{LUMAR_BINARY};
    argv.insert(argv.end(), args.begin(), args.end());
    std::vector<char*> cargv;
    for (auto& a : argv)
        cargv.push_back(a.data());
    cargv.push_back(nullptr);
    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    posix_spawn_file_actions_addopen(&actions, 1, log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    posix_spawn_file_actions_adddup2(&actions, 1, 2);
    pid_t pid = -1;
    const int rc = posix_spawn(&pid, LUMAR_BINARY, &actions, nullptr, cargv.data(), environ);
    posix_spawn_file_actions_destroy(&actions);
    return rc == 0 ? pid : -1;
}

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
    const pid_t pid = spawnLumar({"run", "--config", (dir / "scene.toml").string()}, dir / "log.txt");
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
