// Runs the lumar binary as a user would and captures its exit code, stdout and stderr.
#pragma once

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <fcntl.h>
#include <gtest/gtest.h>
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
    cargv.reserve(argv.size() + 1);
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

// Removes the scratch directories of a test program when it ends having passed; one that
// failed keeps them to be looked at. (Every run of the suite left ~110 MB in /tmp before.)
class ScratchDirectories final : public ::testing::EmptyTestEventListener {
public:
    // The one instance, registered with GoogleTest (which owns it) on first use.
    static ScratchDirectories& instance()
    {
        static ScratchDirectories* const listener = [] {
            auto* made = new ScratchDirectories;
            ::testing::UnitTest::GetInstance()->listeners().Append(made);
            return made;
        }();
        return *listener;
    }

    void add(const std::filesystem::path& dir) { dirs_.push_back(dir); }

    void OnTestProgramEnd(const ::testing::UnitTest& unitTest) override
    {
        if (!unitTest.Passed())
            return;
        for (const std::filesystem::path& dir : dirs_) {
            std::error_code ignored; // a directory already gone is what was wanted
            std::filesystem::remove_all(dir, ignored);
        }
    }

private:
    ScratchDirectories() = default;
    std::vector<std::filesystem::path> dirs_;
};

// A fresh, empty directory for one test, removed when the test program ends if it passed.
inline std::filesystem::path scratchDirectory(const std::string& name)
{
    auto dir = std::filesystem::temp_directory_path() / ("lumar-test-" + name + "-" + std::to_string(::getpid()));
    std::filesystem::remove_all(dir);
    std::filesystem::create_directories(dir);
    ScratchDirectories::instance().add(dir);
    return dir;
}

// The preview window tests' scene (issue 21): one camera image played over and over by the
// `images` source, a cube drawn on its tag, no state that changes from frame to frame once the
// tag is found; `extra` is appended (a reload's edit).
inline std::string stillScene(const std::string& extra = "")
{
    return "[camera]\nsource = \"images\"\npath = \"frames\"\n"
           "[rendering]\nenvironment_maps = \"off\"\n"
           "[environment]\nmatch_exposure = false\n"
           "[[markers]]\nid = 0\nsize = 0.16\n"
           "[[objects]]\nname = \"cube\"\nmodel = \"builtin:cube\"\nmarker = 0\nsize = 0.08\n" +
           extra;
}

// Lays out `dir` for a still scene: frames/f.png, the one camera image (`lumar render` of the
// fake camera at `width` x `height`), scene.toml holding `sceneText` (whose camera reads
// frames/), and headless.png, the frame `lumar render` writes for that scene once the tag is
// found: what a window showing the scene must show. Returns the first failed run, or the last.
inline ProcessResult prepareStillScene(const std::filesystem::path& dir, int width, int height,
                                       const std::string& sceneText)
{
    std::filesystem::create_directories(dir / "frames");
    std::ofstream(dir / "camera.toml") << "[camera]\nwidth = " << width << "\nheight = " << height << "\n";
    ProcessResult r = runLumar({"render", "--config", (dir / "camera.toml").string(), "--frames", "1", "--out",
                                (dir / "frames" / "f.png").string()},
                               dir);
    if (r.exitCode != 0)
        return r;
    std::ofstream(dir / "scene.toml") << sceneText;
    return runLumar({"render", "--config", (dir / "scene.toml").string(), "--frames", "5", "--out",
                     (dir / "headless.png").string()},
                    dir);
}

} // namespace lumar::test
