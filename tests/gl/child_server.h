// A display server a test starts for itself (Xvfb, weston): a child process that lives as
// long as the object, stopped with SIGTERM and reaped when the test ends. What differs between
// servers (their arguments, how they say they are ready) stays with xvfb_server.h and
// weston_server.h.
#pragma once

#include <chrono>
#include <csignal>
#include <functional>
#include <string>
#include <string_view>
#include <thread>
#include <vector>

#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

extern char** environ;

namespace lumar::test {

// This process' environment less the variables whose names start with one of `dropped`
// (e.g. "WAYLAND_", so a server does not connect to the session's own compositor), plus `added`.
inline std::vector<std::string> environmentWith(const std::vector<std::string>& added,
                                                const std::vector<std::string>& dropped = {})
{
    std::vector<std::string> environment = added;
    for (char** e = environ; *e; ++e) {
        bool keep = true;
        for (const std::string& prefix : dropped)
            keep = keep && std::string_view(*e).rfind(prefix, 0) != 0;
        if (keep)
            environment.emplace_back(*e);
    }
    return environment;
}

// Polls `done` every 50 ms until it holds (true) or `limit` has passed (false).
inline bool waitUntil(const std::function<bool()>& done, std::chrono::milliseconds limit)
{
    const auto deadline = std::chrono::steady_clock::now() + limit;
    while (!done()) {
        if (std::chrono::steady_clock::now() > deadline)
            return false;
        std::this_thread::sleep_for(std::chrono::milliseconds(50));
    }
    return true;
}

class ChildServer {
public:
    ChildServer() = default;
    ~ChildServer() { stop(); }
    ChildServer(const ChildServer&) = delete;
    ChildServer& operator=(const ChildServer&) = delete;

    // Starts `args[0]` (looked up in PATH) with `environment` (this process' when empty), its
    // stdout and stderr to `log` (/dev/null when empty), `closeInChild` (a pipe end the child
    // must not hold, or -1) closed in it; every other descriptor is inherited. False when it
    // could not be started.
    bool start(std::vector<std::string> args, std::vector<std::string> environment, const std::string& log = "",
               int closeInChild = -1)
    {
        std::vector<char*> argv;
        for (auto& a : args)
            argv.push_back(a.data());
        argv.push_back(nullptr);
        std::vector<char*> envp;
        for (auto& e : environment)
            envp.push_back(e.data());
        envp.push_back(nullptr);
        const std::string out = log.empty() ? "/dev/null" : log;
        posix_spawn_file_actions_t actions;
        posix_spawn_file_actions_init(&actions);
        if (closeInChild >= 0)
            posix_spawn_file_actions_addclose(&actions, closeInChild);
        posix_spawn_file_actions_addopen(&actions, 1, out.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0600);
        posix_spawn_file_actions_adddup2(&actions, 1, 2);
        const int rc = posix_spawnp(&pid_, args.front().c_str(), &actions, nullptr, argv.data(),
                                    environment.empty() ? environ : envp.data());
        posix_spawn_file_actions_destroy(&actions);
        if (rc != 0)
            pid_ = -1;
        return pid_ > 0;
    }

    // Whether the server is still there (false once it has exited: it is reaped then).
    [[nodiscard]] bool running()
    {
        int status = 0;
        if (pid_ > 0 && ::waitpid(pid_, &status, WNOHANG) == pid_)
            pid_ = -1;
        return pid_ > 0;
    }

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
};

} // namespace lumar::test
