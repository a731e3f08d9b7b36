// The subcommands of the lumar binary (DESIGN.md §2). Each takes its options already parsed
// and checked (lumar_command_line.cpp declares them: names, types, ranges, defaults, help),
// writes its result to stdout, logs to stderr, and returns an exit code; InputError,
// RuntimeError and UsageError thrown out of them are turned into exit codes there.
#pragma once

#include <optional>
#include <string>
#include <vector>

namespace lumar {

struct Config;

// --config FILE and --log-level SPEC, shared by the commands that run the pipeline.
struct ConfigOptions {
    std::optional<std::string> file;     // absent: the built-in default configuration
    std::optional<std::string> logLevel; // absent: the configuration's log_level
};

struct RenderCommandOptions {
    ConfigOptions config;
    long frames = 30;
    std::vector<std::string> outputs; // at least one
    std::optional<std::string> trace;
};

struct RunCommandOptions {
    ConfigOptions config;
    long frames = 0;      // 0: until SIGINT or SIGTERM
    bool preview = false; // show the frames in a desktop window ([output] sink = "window")
    bool overlay = false; // draw the setup view ([output] overlay = true)
};

struct CheckConfigCommandOptions {
    std::string file;
};

struct DetectCommandOptions {
    double tagSize = 0;
    std::optional<std::string> calibration;
    std::string family = "tag36h11";
    double decimate = 1.0;
    std::string logLevel = "warn";
    std::vector<std::string> images; // at least one
    // A lumar config: its [[markers]] sizes, [[maps]] and [tracking] filter settings.
    std::optional<std::string> config;
    bool sequence = false; // the images are consecutive frames of one video
    double fps = 30.0;     // with sequence: their rate
};

struct BenchCommandOptions {
    ConfigOptions config;
    long frames = 300;
    long warmup = 10;
    bool json = false;
    bool noProfile = false;
    bool syncDetection = false;
    std::string environmentSource; // overrides [environment] source when set
    bool replay = false;           // frames captured before timing, served from memory
    // Held frames are RGB plus luma (3.7 MB each at 1280x720), memory a device with a camera does
    // not hold: 4 instead of 8 took car.toml's peak RSS from 208 to 194 MB at the same fps
    // (issue 18; medians of 5 interleaved runs).
    long replayFrames = 4;
};

struct ProbeCommandOptions {
    std::vector<std::string> devices; // in addition to every /dev/video*
};

struct CalibrateCommandOptions {
    std::string images;
    int boardColumns = 0, boardRows = 0; // inner corners
    double square = 0;
    std::string out;
    std::string logLevel = "warn";
};

struct MarkersCommandOptions {
    std::string family = "tag36h11";
    std::string ids;
    double size = 0; // metres, as [[markers]] size
    std::string out; // .pdf, .png or .svg
    std::string page = "a4";
    long dpi = 300;                // .png only
    std::string board;             // ROWSxCOLS; empty: single tags
    std::optional<double> spacing; // board: metres between borders; absent: the white rings
    std::string mapName = "board";
    std::optional<std::string> mapOut; // board: absent: --out with .toml
    std::string logLevel = "warn";
};

int renderCommand(const RenderCommandOptions& options);
int runCommand(const RunCommandOptions& options);
int checkConfigCommand(const CheckConfigCommandOptions& options);
int detectCommand(const DetectCommandOptions& options);
int benchCommand(const BenchCommandOptions& options);
int probeCommand(const ProbeCommandOptions& options);
int calibrateCommand(const CalibrateCommandOptions& options);
int markersCommand(const MarkersCommandOptions& options);

// lumar bench --tracking parses its own arguments (those after "bench").
using Args = std::vector<std::string>;
int trackingBenchCommand(const Args& args);

// Applies a --log-level SPEC; throws UsageError for a malformed one.
void configureLogLevel(const std::string& spec);

// Loads --config FILE if given, else the built-in default, and applies its log level unless
// --log-level overrides it.
Config configFromOptions(const ConfigOptions& options);

} // namespace lumar
