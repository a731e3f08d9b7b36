// lumar bench --tracking: the tracking benchmark is its own program, lumar-bench-tracking
// (bench/), so that the shipped lumar does not link what only the benchmark needs (OpenCV's
// contrib aruco module and its dependency closure). It is built next to lumar in the build
// tree and never installed; there this command runs it with the same options, elsewhere it
// says where the benchmark is.
#include <cerrno>
#include <filesystem>
#include <string>
#include <system_error>
#include <vector>

#include <unistd.h>

#include "commands.h"
#include "core/error.h"

namespace lumar {

int trackingBenchCommand(const Args& args)
{
    constexpr const char* kProgram = "lumar-bench-tracking";
    std::error_code ec;
    const std::filesystem::path self = std::filesystem::read_symlink("/proc/self/exe", ec);
    const std::filesystem::path bench = self.parent_path() / kProgram;
    if (ec || ::access(bench.c_str(), X_OK) != 0)
        throw RuntimeError(std::string("bench --tracking: the tracking benchmark is the separate program ") + kProgram +
                           ", built in lumar's build tree and not installed");
    std::vector<std::string> arguments{bench.string()};
    for (const std::string& a : args)
        if (a != "--tracking")
            arguments.push_back(a);
    std::vector<char*> argv;
    for (std::string& a : arguments)
        argv.push_back(a.data());
    argv.push_back(nullptr);
    ::execv(bench.c_str(), argv.data());
    throw RuntimeError(bench.string() + ": cannot run: " + std::generic_category().message(errno));
}

} // namespace lumar
