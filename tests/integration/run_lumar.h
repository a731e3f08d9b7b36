// Runs the lumar binary as a user would and captures its exit code, stdout and stderr.
#pragma once

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

namespace lumar::test {

struct ProcessResult {
    int exitCode = -1;
    std::string out;
    std::string err;
};

inline std::string readText(const std::filesystem::path& file)
{
    std::ifstream in(file);
    std::stringstream s;
    s << in.rdbuf();
    return s.str();
}

inline std::string shellQuote(const std::string& s)
{
    std::string q = "'";
    for (char c : s)
        q += c == '\'' ? std::string("'\\''") : std::string(1, c);
    return q + "'";
}

// `args` are passed to lumar quoted one by one; `environment` ("NAME=value" items) is set
// for this run only.
inline ProcessResult runLumar(const std::vector<std::string>& args, const std::filesystem::path& workDir,
                              const std::vector<std::string>& environment = {})
{
    const auto outFile = workDir / "stdout.txt", errFile = workDir / "stderr.txt";
    std::string command = "env";
    for (const std::string& e : environment)
        command += " " + shellQuote(e);
    command += " " + shellQuote(LUMAR_BINARY);
    for (const std::string& a : args)
        command += " " + shellQuote(a);
    command += " >" + shellQuote(outFile) + " 2>" + shellQuote(errFile) + " </dev/null";
    const int status = std::system(command.c_str());
    ProcessResult r;
    r.exitCode = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    r.out = readText(outFile);
    r.err = readText(errFile);
    return r;
}

// A fresh, empty directory for one test.
// Starts lumar (LUMAR_BINARY) with stdout/stderr redirected to `log` and `extraEnvironment`
// ("NAME=value") added to this process' environment; returns its pid, -1 when it could not.
inline pid_t spawnLumar(const std::vector<std::string>& args, const std::filesystem::path& log,
                        std::vector<std::string> extraEnvironment = {})
{
    std::vector<char*> envp;
    for (char** e = environ; *e; ++e)
        envp.push_back(*e);
    for (auto& e : extraEnvironment)
        envp.push_back(e.data());
    envp.push_back(nullptr);
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
    const int rc = posix_spawn(&pid, LUMAR_BINARY, &actions, nullptr, cargv.data(), envp.data());
    posix_spawn_file_actions_destroy(&actions);
    return rc == 0 ? pid : -1;
}

inline std::filesystem::path scratchDirectory(const std::string& name)
{
    const auto dir = std::filesystem::temp_directory_path() / ("lumar-test-" + name + "-" + std::to_string(::getpid()));
    std::filesystem::remove_all(dir);
    std::filesystem::create_directories(dir);
    return dir;
}

} // namespace lumar::test
