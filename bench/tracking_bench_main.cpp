// lumar-bench-tracking: scores lumar's tag tracker against the AprilTag library's defaults
// (and OpenCV's ArUco where built) on a synthetic sequence with exact ground truth and prints
// one table (bench/tracking_bench.h). Measured, never asserted in tests (DESIGN.md §9).
// Exit codes as lumar's: 0 success, 1 runtime failure, 2 bad usage or bad input.
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "bench/tracking_bench.h"
#include "bench/tracking_overhead.h"
#include "bench/tracking_sequences.h"
#include "core/error.h"
#include "core/log.h"

namespace {

constexpr const char* kProgram = "lumar-bench-tracking";

constexpr const char* kDescription = "The tracking benchmark: lumar's tag tracker against the AprilTag library's "
                                     "defaults and OpenCV's ArUco, on synthetic frames with exact ground truth.";

constexpr const char* kDetails =
    R"(Renders a deterministic synthetic sequence with exact ground truth (conditions: clean, noise,
motion blur, defocus, low light, views up to 75 degrees from the tag normal, partial occlusion,
several tags, frames without tags) and runs on every frame, one thread each: lumar's tracker
as configured by default, the AprilTag library with its defaults, and OpenCV's ArUco detector
with DICT_APRILTAG_36h11 where this build has it. Prints one markdown table (condition x
detector): recall, false positives per frame, corner error (mean, p95, px), rotation error
(deg), translation error (% of distance), ms per frame; and lumar's time per frame over the
AprilTag defaults'. Also run by `lumar bench --tracking` in the build tree.)";

} // namespace

int main(int argc, char** argv)
{
    CLI::App app(kDescription, kProgram);
    app.footer(kDetails);
    lumar::TrackingBenchOptions options;
    bool json = false;
    // Quiet by default: the tracker logs its settings each time a condition restarts it.
    std::string logLevel = "warn";
    app.add_option("--frames-per-condition", options.framesPerCondition, "frames rendered per condition")
        ->check(CLI::Range(1, 10000))
        ->capture_default_str();
    app.add_option("--width", options.width, "frame width in pixels")
        ->check(CLI::Range(64, 8192))
        ->capture_default_str();
    app.add_option("--height", options.height, "frame height in pixels")
        ->check(CLI::Range(64, 8192))
        ->capture_default_str();
    app.add_option("--seed", options.seed, "seed of the camera path, clutter and noise")
        ->check(CLI::Range(uint64_t(0), uint64_t(1) << 62))
        ->capture_default_str();
    app.add_flag("--json", json, "one JSON object instead of the table");
    bool overhead = false;
    lumar::TrackingOverheadOptions overheadOptions;
    app.add_flag("--overhead", overhead,
                 "instead: lumar's tracker against the library's detection call on the same luma planes\n"
                 "(full frame, stills, video), interleaved rounds, medians (bench/tracking_overhead.h)");
    app.add_option("--overhead-frames", overheadOptions.frames, "with --overhead: frames per round")
        ->check(CLI::Range(1, 1000))
        ->capture_default_str();
    app.add_option("--overhead-rounds", overheadOptions.rounds, "with --overhead: rounds")
        ->check(CLI::Range(1, 100))
        ->capture_default_str();
    bool sequences = false;
    int rounds = 1;
    app.add_flag("--sequences", sequences,
                 "instead: temporal sequences (a tag lost for one frame in low light, occlusions ending at\n"
                 "any phase, a tag leaving and re-entering, a fast pan with blur, a 4-tag board): recall,\n"
                 "re-acquisition delay, jitter, lag, ms per frame (bench/tracking_sequences.h)");
    app.add_option("--rounds", rounds, "with --sequences: interleaved rounds (ms: median)")
        ->check(CLI::Range(1, 100))
        ->capture_default_str();
    std::vector<std::string> lumarVariants;
    app.add_option("--lumar", lumarVariants,
                   "with --sequences: a configuration of lumar's tracker to run, NAME or NAME:key=value,...\n"
                   "with [tracking] keys of lumar.toml (threads 1 unless given); repeatable; default:\n"
                   "'lumar' (defaults, threads 1) and 'lumar_2threads' (threads 2)");
    const char* dataEnv = std::getenv("LUMAR_DATA_DIR");
    std::string dataDir = dataEnv && *dataEnv ? dataEnv : LUMAR_SHARED_DATA_DIR;
    app.add_option("--data", dataDir,
                   "with --sequences: the shared data folder with apriltag/real/ (the library's test photos,\n"
                   "run as still sequences; skipped when absent); default: $LUMAR_DATA_DIR or the build's")
        ->capture_default_str();
    int photoFrames = 20;
    app.add_option("--photo-frames", photoFrames, "with --sequences: frames per photo sequence")
        ->check(CLI::Range(2, 1000))
        ->capture_default_str();
    app.add_option("--log-level", logLevel, "e.g. info, or tracking:debug,*:warn")->capture_default_str();
    try {
        app.parse(argc, argv);
    } catch (const CLI::CallForHelp&) {
        std::fputs(app.help().c_str(), stdout);
        return lumar::kExitOk;
    } catch (const CLI::ParseError& e) {
        std::fprintf(stderr, "%s: %s (see '%s --help')\n", kProgram, e.what(), kProgram);
        return lumar::kExitBadInput;
    }
    try {
        if (!lumar::log::configure(logLevel)) {
            std::fprintf(stderr, "%s: bad log level '%s' (e.g. info, or capture:debug,*:warn)\n", kProgram,
                         logLevel.c_str());
            return lumar::kExitBadInput;
        }
        if (overhead) {
            overheadOptions.width = options.width;
            overheadOptions.height = options.height;
            overheadOptions.seed = options.seed;
            std::fputs(lumar::runTrackingOverhead(overheadOptions).c_str(), stdout);
            return lumar::kExitOk;
        }
        if (sequences) {
            lumar::TrackingSequencesOptions sequenceOptions;
            sequenceOptions.width = options.width;
            sequenceOptions.height = options.height;
            sequenceOptions.seed = options.seed;
            sequenceOptions.rounds = rounds;
            for (const std::string& text : lumarVariants)
                sequenceOptions.lumar.push_back(lumar::parseLumarVariant(text));
            sequenceOptions.dataDir = dataDir;
            sequenceOptions.photoFrames = photoFrames;
            const lumar::TrackingSequencesReport report = lumar::runTrackingSequences(sequenceOptions);
            std::fputs((json ? lumar::trackingSequencesJson(report) : lumar::trackingSequencesMarkdown(report)).c_str(),
                       stdout);
            return lumar::kExitOk;
        }
        const lumar::TrackingBenchReport report = lumar::runTrackingBench(options);
        const std::string text = json ? lumar::trackingBenchJson(report) : lumar::trackingBenchMarkdown(report);
        std::fputs(text.c_str(), stdout);
        return lumar::kExitOk;
    } catch (const lumar::InputError& e) {
        std::fprintf(stderr, "%s: %s\n", kProgram, e.what());
        return lumar::kExitBadInput;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "%s: %s\n", kProgram, e.what());
        return lumar::kExitRuntime;
    }
}
