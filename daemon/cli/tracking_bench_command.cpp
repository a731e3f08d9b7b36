// lumar bench --tracking: scores lumar's tag tracker against the AprilTag library's defaults
// (and OpenCV's ArUco where built) on a synthetic sequence with exact ground truth and prints
// one table (tracking/tracking_bench.h). Measured, never asserted in tests (DESIGN.md §9).
#include <cstdint>
#include <cstdio>
#include <string>

#include "command_line.h"
#include "commands.h"
#include "core/error.h"
#include "core/log.h"
#include "tracking/tracking_bench.h"

namespace lumar {
namespace {

constexpr const char* kHelp =
    R"(usage: lumar bench --tracking [--frames-per-condition N] [--width W] [--height H] [--seed S] [--json]
                    [--log-level SPEC]

Renders a deterministic synthetic sequence with exact ground truth (conditions: clean, noise,
motion blur, defocus, low light, views up to 75 degrees from the tag normal, partial occlusion,
several tags, frames without tags) and runs on every frame, one thread each: lumar's tracker
as configured by default, the AprilTag library with its defaults, and OpenCV's ArUco detector
with DICT_APRILTAG_36h11 where this build has it. Prints one markdown table (condition x
detector): recall, false positives per frame, corner error (mean, p95, px), rotation error
(deg), translation error (% of distance), ms per frame; and lumar's time per frame over the
AprilTag defaults'.
  --frames-per-condition N   default 30
  --width W, --height H      default 1280x720
  --seed S                   default 1
  --json                     one JSON object instead of the table
)";

} // namespace

int trackingBenchCommand(const Args& args)
{
    const CommandLine cl(args, {{"tracking", false},
                                {"frames-per-condition"},
                                {"width"},
                                {"height"},
                                {"seed"},
                                {"json", false},
                                {"log-level"}});
    if (cl.helpRequested()) {
        std::fputs(kHelp, stdout);
        return kExitOk;
    }
    if (!cl.positional().empty())
        throw UsageError("unexpected argument '" + cl.positional().front() + "'");
    // Quiet by default: the tracker logs its settings each time a condition restarts it.
    const std::string level = cl.value("log-level").value_or("warn");
    if (!log::configure(level))
        throw UsageError("bad log level '" + level + "' (e.g. info, or capture:debug,*:warn)");
    TrackingBenchOptions options;
    options.framesPerCondition = int(cl.integer("frames-per-condition", 30, 1, 10000));
    options.width = int(cl.integer("width", 1280, 64, 8192));
    options.height = int(cl.integer("height", 720, 64, 8192));
    options.seed = uint64_t(cl.integer("seed", 1, 0, 1L << 62));
    const TrackingBenchReport report = runTrackingBench(options);
    const std::string text = cl.has("json") ? trackingBenchJson(report) : trackingBenchMarkdown(report);
    std::fputs(text.c_str(), stdout);
    return kExitOk;
}

} // namespace lumar
