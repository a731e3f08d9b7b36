// lumar: photorealistic AR for embedded Linux. Subcommand dispatch and the outermost error
// boundary: bad input exits 2, a runtime failure exits 1, with one line on stderr.
#include <cstdio>
#include <exception>
#include <string>
#include <vector>

#include "command_line.h"
#include "commands.h"
#include "core/error.h"

namespace {

constexpr const char* kUsage = R"(usage: lumar <command> [options]

commands:
  render        render N frames offline (deterministic) to PNG and/or Y4M files
  run           the daemon: capture, track and render continuously
  check-config  validate a configuration file
  detect        detect AprilTags in images and print their poses as JSON
  bench         time the pipeline: fps, frame-time percentiles, per-stage times, memory
  probe         list cameras and formats, the EGL/GLES implementation, display devices
  calibrate     camera intrinsics from chessboard photos, written as OpenCV YAML

Run 'lumar <command> --help' for a command's options.
Exit codes: 0 success, 1 runtime failure, 2 bad usage or bad input.
)";

struct Command {
    const char* name;
    int (*run)(const lumar::Args&);
};

constexpr Command kCommands[] = {
    {"render", lumar::renderCommand},       {"run", lumar::runCommand},     {"check-config", lumar::checkConfigCommand},
    {"detect", lumar::detectCommand},       {"bench", lumar::benchCommand}, {"probe", lumar::probeCommand},
    {"calibrate", lumar::calibrateCommand},
};

} // namespace

int main(int argc, char** argv)
{
    if (argc < 2) {
        std::fputs(kUsage, stderr);
        return lumar::kExitBadInput;
    }
    const std::string name = argv[1];
    if (name == "--help" || name == "-h" || name == "help") {
        std::fputs(kUsage, stdout);
        return lumar::kExitOk;
    }
    const lumar::Args args(argv + 2, argv + argc);
    for (const Command& command : kCommands) {
        if (name != command.name)
            continue;
        try {
            return command.run(args);
        } catch (const lumar::UsageError& e) {
            std::fprintf(stderr, "lumar %s: %s (see 'lumar %s --help')\n", command.name, e.what(), command.name);
            return lumar::kExitBadInput;
        } catch (const lumar::InputError& e) {
            std::fprintf(stderr, "lumar: %s\n", e.what());
            return lumar::kExitBadInput;
        } catch (const std::exception& e) {
            std::fprintf(stderr, "lumar: %s\n", e.what());
            return lumar::kExitRuntime;
        }
    }
    std::fprintf(stderr, "lumar: unknown command '%s'\n\n%s", name.c_str(), kUsage);
    return lumar::kExitBadInput;
}
