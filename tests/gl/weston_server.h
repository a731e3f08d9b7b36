// A private Wayland compositor for tests: weston on its headless backend (no GPU, no input
// devices), in a runtime directory of its own, killed when the test ends. Its kiosk shell
// makes every toplevel fill the one output, so a window's size is the output's. Tests skip
// when weston is not installed.
#pragma once

#include <chrono>
#include <csignal>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <thread>
#include <vector>

#include <fcntl.h>
#include <spawn.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

extern char** environ;

namespace lumar::test {

class WestonServer {
public:
    [[nodiscard]] static bool installed() { return std::system("command -v weston >/dev/null 2>&1") == 0; }

    // Starts weston with one `width` x `height` output; socket() is empty when it could not be
    // started (within 30 s).
    explicit WestonServer(int width = 320, int height = 240)
    {
        char pattern[] = "/tmp/lumar-weston-XXXXXX";
        if (!::mkdtemp(pattern))
            return;
        runtimeDir_ = pattern;
        const std::string name = "wayland-lumar-test";
        std::vector<std::string> args{"weston",
                                      "--backend=headless-backend.so",
                                      "--shell=kiosk-shell.so",
                                      "--socket=" + name,
                                      "--width=" + std::to_string(width),
                                      "--height=" + std::to_string(height),
                                      "--idle-time=0",
                                      "--no-config"};
        std::vector<char*> argv;
        for (auto& a : args)
            argv.push_back(a.data());
        argv.push_back(nullptr);
        std::vector<std::string> environment{"XDG_RUNTIME_DIR=" + runtimeDir_};
        for (char** e = environ; *e; ++e)
            if (std::string_view(*e).rfind("XDG_RUNTIME_DIR=", 0) != 0 &&
                std::string_view(*e).rfind("WAYLAND_", 0) != 0)
                environment.emplace_back(*e);
        std::vector<char*> envp;
        for (auto& e : environment)
            envp.push_back(e.data());
        envp.push_back(nullptr);
        posix_spawn_file_actions_t actions;
        posix_spawn_file_actions_init(&actions);
        const std::string log = runtimeDir_ + "/weston.log";
        posix_spawn_file_actions_addopen(&actions, 1, log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0600);
        posix_spawn_file_actions_addopen(&actions, 2, log.c_str(), O_WRONLY | O_APPEND, 0600);
        const int rc = posix_spawnp(&pid_, "weston", &actions, nullptr, argv.data(), envp.data());
        posix_spawn_file_actions_destroy(&actions);
        if (rc != 0) {
            pid_ = -1;
            return;
        }
        // The socket appears once weston accepts clients.
        const std::string path = runtimeDir_ + "/" + name;
        for (int i = 0; i < 600; ++i) {
            struct stat st {};
            if (::stat(path.c_str(), &st) == 0 && S_ISSOCK(st.st_mode)) {
                socket_ = path;
                name_ = name;
                break;
            }
            int status = 0;
            if (::waitpid(pid_, &status, WNOHANG) == pid_) {
                pid_ = -1;
                break;
            }
            std::this_thread::sleep_for(std::chrono::milliseconds(50));
        }
    }
    ~WestonServer()
    {
        stop();
        if (!runtimeDir_.empty()) {
            std::error_code ignored;
            std::filesystem::remove_all(runtimeDir_, ignored);
        }
    }
    WestonServer(const WestonServer&) = delete;
    WestonServer& operator=(const WestonServer&) = delete;

    // The socket's absolute path (what wl_display_connect takes), empty when weston did not start.
    [[nodiscard]] const std::string& socket() const { return socket_; }
    // For a child process: XDG_RUNTIME_DIR and WAYLAND_DISPLAY.
    [[nodiscard]] const std::string& runtimeDir() const { return runtimeDir_; }
    [[nodiscard]] const std::string& name() const { return name_; }

    void stop()
    {
        if (pid_ > 0) {
            ::kill(pid_, SIGTERM);
            int status = 0;
            ::waitpid(pid_, &status, 0);
        }
        pid_ = -1;
    }

private:
    pid_t pid_ = -1;
    std::string runtimeDir_;
    std::string socket_;
    std::string name_;
};

} // namespace lumar::test
