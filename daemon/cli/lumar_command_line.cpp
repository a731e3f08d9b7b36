// Every lumar command is declared here, once: its options with their types, ranges, defaults
// and whether they are required, and the prose of its --help. CLI11 parses and generates the
// help pages. This is the only file that includes it: CLI11 2.1 is header-only and heavy
// (#include <CLI/CLI.hpp> alone costs ~13.6 s of CPU at -O2 -g here, this file ~16.6 s; the
// rest of daemon/cli together ~33 s), so the formatter and helpers stay here too.
#include "lumar_command_line.h"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <functional>
#include <optional>
#include <sstream>

#include <CLI/CLI.hpp>

#include "commands.h"
#include "core/error.h"
#include "usage_error.h"

namespace lumar {
namespace {

// ---- Help pages -------------------------------------------------------------------------

// A page reads: the usage line listing every option (so that README's Commands block can be
// held against it), the description (its first line is the summary `lumar --help` lists),
// the arguments and options, each with "(required)", "(repeatable)" and its default, the
// footer and the exit codes.
class HelpFormatter : public CLI::Formatter {
public:
    HelpFormatter()
    {
        label("Usage", "usage");
        label("Positionals", "arguments");
        column_width(26);
    }

    std::string make_help(const CLI::App* app, std::string name, CLI::AppFormatMode mode) const override
    {
        return make_usage(app, name) + "\n" + app->get_description() + "\n" + make_positionals(app) +
               make_groups(app, mode) + make_subcommands(app, mode) + "\n" + make_footer(app);
    }

    std::string make_usage(const CLI::App* app, std::string name) const override
    {
        std::string usage = get_label("Usage") + ": " + name;
        if (!app->get_subcommands({}).empty())
            usage += " <command> [options]";
        size_t lineStart = 0;
        for (const CLI::Option* option : app->get_options()) {
            if (option == app->get_help_ptr())
                continue;
            std::string word = option->get_positional() ? option->get_name(true, false) : option->get_name(false, true);
            if (option->nonpositional() && !option->get_type_name().empty())
                word += " " + option->get_type_name();
            if (repeatable(option))
                word += "...";
            if (!option->get_required())
                word = "[" + word + "]";
            // Continuation lines start under the first option.
            if (usage.size() - lineStart + 1 + word.size() > 100) {
                lineStart = usage.size() + 1;
                usage += "\n" + std::string(get_label("Usage").size() + name.size() + 2, ' ') + word;
            } else {
                usage += " " + word;
            }
        }
        return usage + "\n";
    }

    std::string make_option_opts(const CLI::Option* option) const override
    {
        return option->get_positional() || option->get_type_name().empty() ? "" : " " + option->get_type_name();
    }

    std::string make_option_desc(const CLI::Option* option) const override
    {
        std::string notes;
        const auto note = [&notes](const std::string& text) { notes += (notes.empty() ? "" : ", ") + text; };
        if (option->get_required())
            note("required");
        if (repeatable(option))
            note("repeatable");
        if (!option->get_default_str().empty())
            note("default " + option->get_default_str());
        // Behind the first line of a description that takes several.
        std::string description = option->get_description();
        if (!notes.empty())
            description.insert(std::min(description.find('\n'), description.size()), " (" + notes + ")");
        return description;
    }

    std::string make_footer(const CLI::App* app) const override
    {
        const std::string& footer = app->get_footer();
        return (footer.empty() ? "" : footer + "\n\n") +
               "Exit codes: 0 success, 1 runtime failure, 2 bad usage or bad input.\n";
    }

    // `lumar --help` lists each command with the first line of its description.
    std::string make_subcommand(const CLI::App* command) const override
    {
        const std::string& description = command->get_description();
        std::stringstream out;
        CLI::detail::format_help(out, command->get_name(), description.substr(0, description.find('\n')),
                                 column_width_);
        return out.str();
    }

private:
    static bool repeatable(const CLI::Option* option)
    {
        return option->get_expected_max() >= CLI::detail::expected_max_vector_size;
    }
};

// ---- Typed options ----------------------------------------------------------------------

// The bounds of a numeric option, written and checked as an interval: [1, 1000000], (0, 1000].
struct Range {
    double min, max;
    bool minExcluded = false;

    bool contains(double v) const { return (minExcluded ? v > min : v >= min) && v <= max; }
    std::string text() const
    {
        char out[80];
        std::snprintf(out, sizeof out, "%c%.15g, %.15g]", minExcluded ? '(' : '[', min, max);
        return out;
    }
};

std::string showNumber(double v)
{
    char out[32];
    std::snprintf(out, sizeof out, "%.15g", v);
    return out;
}

// Numbers are read whole, in base 10 (CLI11's own conversion would read "010" as octal).
std::optional<long> parseInteger(const std::string& text)
{
    errno = 0;
    char* end = nullptr;
    const long v = std::strtol(text.c_str(), &end, 10);
    if (text.empty() || *end != '\0' || errno == ERANGE)
        return std::nullopt;
    return v;
}

std::optional<double> parseNumber(const std::string& text)
{
    char* end = nullptr;
    const double v = std::strtod(text.c_str(), &end);
    if (text.empty() || *end != '\0' || !std::isfinite(v))
        return std::nullopt;
    return v;
}

// An option whose value is read by `parse` (no value when the text is not `what`) and
// checked against `range`; its help line shows the range and the default.
template <typename T, typename Parse>
CLI::Option* addNumber(CLI::App& command, const std::string& name, T& target, Range range, const std::string& typeName,
                       const std::string& help, Parse parse, const char* what)
{
    const auto assign = [&target, name, range, parse, what](const std::string& text) {
        const auto value = parse(text);
        if (!value)
            throw CLI::ValidationError(name, "'" + text + "' is not " + what);
        if (!range.contains(double(*value)))
            throw CLI::ValidationError(name, text + " is outside " + range.text());
        target = T(*value);
    };
    return command.add_option_function<std::string>(name, assign, help + ", " + range.text())
        ->type_name(typeName)
        ->default_str(showNumber(double(target)));
}

CLI::Option* addInteger(CLI::App& command, const std::string& name, long& target, Range range, const std::string& help)
{
    return addNumber(command, name, target, range, "N", help, parseInteger, "an integer");
}

CLI::Option* addDouble(CLI::App& command, const std::string& name, double& target, Range range,
                       const std::string& typeName, const std::string& help)
{
    return addNumber(command, name, target, range, typeName, help, parseNumber, "a number");
}

// A value that must be given and not be empty.
CLI::Option* addRequired(CLI::App& command, const std::string& name, std::string& target, const std::string& typeName,
                         const std::string& help)
{
    const auto notEmpty = [](const std::string& value) { return value.empty() ? "needs a value" : ""; };
    return command.add_option(name, target, help)->type_name(typeName)->required()->check(CLI::Validator(notEmpty, ""));
}

// A flag: "--json", never "--json=value".
void addFlag(CLI::App& command, const std::string& name, bool& target, const std::string& help)
{
    command.add_flag(name, target, help)->disable_flag_override();
}

// A repeatable option: "--out a.png --out b.y4m", one value each time.
CLI::Option* addRepeatable(CLI::App& command, const std::string& name, std::vector<std::string>& target,
                           const std::string& typeName, const std::string& help)
{
    return command.add_option(name, target, help)->type_name(typeName)->allow_extra_args(false);
}

// --config first and --log-level last, around the command's own options.
void addConfigFile(CLI::App& command, ConfigOptions& options)
{
    command.add_option("--config", options.file, "the configuration (default: the built-in one)")->type_name("FILE");
}

void addConfigLogLevel(CLI::App& command, ConfigOptions& options)
{
    command
        .add_option("--log-level", options.logLevel,
                    "e.g. info, or capture:debug,*:warn (default: the configuration's log_level)")
        ->type_name("SPEC");
}

// --log-level for the commands without a configuration.
void addLogLevel(CLI::App& command, std::string& level)
{
    command.add_option("--log-level", level, "e.g. info, or tracking:debug,*:warn")
        ->type_name("SPEC")
        ->capture_default_str();
}

// ---- The commands -----------------------------------------------------------------------

struct Options {
    RenderCommandOptions render;
    RunCommandOptions run;
    CheckConfigCommandOptions checkConfig;
    DetectCommandOptions detect;
    BenchCommandOptions bench;
    ProbeCommandOptions probe;
    CalibrateCommandOptions calibrate;
    MarkersCommandOptions markers;
};

struct Command {
    CLI::App* app;
    std::function<int()> run;
};

Command declareRender(CLI::App& lumar, RenderCommandOptions& o)
{
    CLI::App* c = lumar.add_subcommand("render", R"(render N frames offline (deterministic) to PNG and/or Y4M files

Renders N frames of the configured scene and writes them to each --out. Without --config the
built-in default runs: fake camera, demo model, HDR environment.)");
    addConfigFile(*c, o.config);
    addInteger(*c, "--frames", o.frames, {1, 1000000}, "frames to render");
    addRepeatable(*c, "--out", o.outputs, "FILE",
                  "out.png: the last frame as a PNG still\n"
                  "out.y4m: every frame as Y4M video (4:2:0, full range)\n"
                  "f_%04d.png: every frame as its own PNG")
        ->required();
    c->add_option("--trace", o.trace, "one JSON line per frame: detections, poses, stage times")->type_name("FILE");
    addConfigLogLevel(*c, o.config);
    return {c, [&o] { return renderCommand(o); }};
}

Command declareRun(CLI::App& lumar, RunCommandOptions& o)
{
    CLI::App* c = lumar.add_subcommand("run", R"(the daemon: capture, track and render continuously

Runs the AR pipeline continuously until SIGINT or SIGTERM (or N frames when --frames is
given). The output goes to the configured sink: [output] path = "x.png" keeps a still of
the newest frame (rewritten once a second, atomically), "x.y4m" records every frame; with
sink = "kms" every frame is shown on a DRM/KMS display (the board profile's [display] and
[output]'s drm_device, connector, plane and mode choose it), or, without a DRM device, the
path is written instead; with sink = "window" (or --preview) every frame is shown in a
desktop window on $DISPLAY, scaled to fit with its aspect kept, and closing the window stops
the run (exit 0); without a display server the path is written instead. The display is
chosen once: a reload keeps it.)");
    addConfigFile(*c, o.config);
    addInteger(*c, "--frames", o.frames, {0, double(1L << 40)}, "stop after N frames, 0: run until stopped");
    addFlag(*c, "--preview", o.preview,
            "show the frames in a desktop window (Wayland or X11; q or Escape in it, or closing it, stops the "
            "run), as [output] sink = \"window\"");
    addFlag(*c, "--overlay", o.overlay,
            "draw the setup view (tag outlines, ids, axes, errors, status) over every frame, as [output] overlay = "
            "true; the key o toggles it in the window");
    addConfigLogLevel(*c, o.config);
    c->footer(R"(The configuration file is reloaded when it changes on disk (editors and mv included) or on
SIGHUP; a file with an error is rejected with its FILE:LINE message and the last good
configuration keeps running. A new file keeps the running camera unless its [camera]
changed, and the GL context unless its [rendering] or display settings changed; models,
markers, maps, objects and tracking settings are replaced in place. The start-up time (to
the first presented frame) and each reload's duration are logged and written to the status
file as startup_ms and last_reload_ms.

Under systemd (Type=notify) it reports READY=1 after the first frame, WATCHDOG=1 while
frames flow, and STATUS= with fps and tracking state.)");
    return {c, [&o] { return runCommand(o); }};
}

Command declareCheckConfig(CLI::App& lumar, CheckConfigCommandOptions& o)
{
    CLI::App* c = lumar.add_subcommand("check-config", R"(validate a configuration file

Validates FILE: syntax, keys, types, ranges and that referenced files exist.
A file with a [board] table is checked as a board profile (board/README.md).
Prints 'FILE: ok' and exits 0, or prints the first error as FILE:LINE: message and exits 2.)");
    c->add_option("FILE", o.file, "configuration or board profile")->required();
    return {c, [&o] { return checkConfigCommand(o); }};
}

Command declareDetect(CLI::App& lumar, DetectCommandOptions& o)
{
    CLI::App* c = lumar.add_subcommand("detect", R"(detect AprilTags in images and print their poses as JSON

Detects AprilTags and prints, per image, one line:
  {"file":..., "detections":[{"id":..,"corners":[[x,y]x4],"R":[[..]x3],"t":[..]}]}
Corners are in the AprilTag library's order, in OpenCV's pixel convention (pixel centres at
integer coordinates). R and t map the tag frame (x right, y up, z out of the tag, metres)
into the camera frame. Without --calib an ideal camera with a 70 degree horizontal field of
view is assumed.
With --config, the file's [[markers]] sizes (by id; --tag-size for the others) and [[maps]]
are used: each line then carries "maps", the boards found, with their poses. With --sequence
the images are consecutive frames of one video (at --fps): the tracker follows the tags from
frame to frame as `lumar run` does, and each line carries "frame", "timestamp_ns" and
"filtered", the filtered poses per tag id and per map that objects would be drawn with.)");
    addDouble(*c, "--tag-size", o.tagSize, {1e-4, 100}, "M", "tag side in metres, black border to black border")
        ->required()
        ->default_str("");
    c->add_option("--calib", o.calibration, "camera calibration (OpenCV YAML, as lumar calibrate writes)")
        ->type_name("FILE");
    c->add_option("--family", o.family, "tag family")->type_name("NAME")->capture_default_str();
    addDouble(*c, "--decimate", o.decimate, {1, 8}, "D", "quad_decimate; 1: full resolution, best for stills");
    c->add_option("--config", o.config, "lumar config: [[markers]] sizes, [[maps]], [tracking] filter")
        ->type_name("FILE");
    c->add_flag("--sequence", o.sequence, "the images are consecutive video frames: follow and filter");
    addDouble(*c, "--fps", o.fps, {1, 1000}, "FPS", "with --sequence: the frame rate");
    addLogLevel(*c, o.logLevel);
    c->add_option("IMAGE", o.images, "images to search (PNG, JPEG)")->required();
    return {c, [&o] { return detectCommand(o); }};
}

Command declareBench(CLI::App& lumar, BenchCommandOptions& o)
{
    CLI::App* c =
        lumar.add_subcommand("bench", R"(time the pipeline: fps, frame-time percentiles, per-stage times, memory

Runs N frames (after the warm-up frames) of the configured scene through the whole pipeline
without pacing or output, and prints frames per second, frame-time percentiles, the mean
time of each stage and the resident memory. Capture runs one frame ahead on its own thread,
so "capture" is the time the pipeline waited for it.
The render stage is split into its parts (environment maps, SH projection with the diffuse
map, glossy prefilter, shading of the frame, the shadow map) by waiting for the GPU between them, which a
GPU would otherwise overlap with the next stage; --no-profile measures without the waits.)");
    addConfigFile(*c, o.config);
    addInteger(*c, "--frames", o.frames, {1, 1000000}, "frames to measure");
    addInteger(*c, "--warmup", o.warmup, {0, 10000}, "frames run before measuring");
    addFlag(*c, "--json", o.json, "one JSON object instead of a table");
    addFlag(*c, "--no-profile", o.noProfile, "do not split the render stage");
    addFlag(*c, "--sync-detection", o.syncDetection,
            "detect in the render loop (as `lumar render` does) instead of on a\n"
            "worker thread (as `lumar run` does); \"detect\" is then time in the loop");
    c->add_option("--environment-source", o.environmentSource,
                  "[environment] source for this run: hdr, camera or camera+hdr\n"
                  "(to compare the environment built from the camera with the file)")
        ->type_name("SOURCE")
        ->check(CLI::IsMember({"hdr", "camera", "camera+hdr"}));
    addFlag(*c, "--replay", o.replay,
            "capture --replay-frames frames before timing and serve them from memory,\n"
            "forwards and back, as a device's camera delivers them: the fake camera's\n"
            "own drawing is left out (without it: the live camera, \"source\": \"live\")");
    addInteger(*c, "--replay-frames", o.replayFrames, {1, 300},
               "frames held for --replay (default 4: 3.7 MB each at 1280x720)");
    addConfigLogLevel(*c, o.config);
    c->footer("lumar bench --tracking [options] scores the tag tracker instead (see 'lumar bench --tracking --help').");
    return {c, [&o] { return benchCommand(o); }};
}

Command declareProbe(CLI::App& lumar, ProbeCommandOptions& o)
{
    CLI::App* c =
        lumar.add_subcommand("probe", R"(list cameras and formats, the EGL/GLES implementation, display devices

Lists V4L2 cameras (every /dev/video*, plus each --device) with their pixel formats and frame
sizes, libcamera cameras with their viewfinder formats and sizes, the EGL/GLES implementation
with the extensions lumar uses, and DRM devices with their connectors, modes and planes.)");
    addRepeatable(*c, "--device", o.devices, "PATH", "a V4L2 device to probe besides /dev/video*");
    return {c, [&o] { return probeCommand(o); }};
}

Command declareCalibrate(CLI::App& lumar, CalibrateCommandOptions& o)
{
    CLI::App* c = lumar.add_subcommand("calibrate", R"(camera intrinsics from chessboard photos, written as OpenCV YAML

Calibrates the camera from photos of a flat chessboard: every *.jpg, *.jpeg and *.png in DIR,
all of one size, taken from varied angles (at least 3 must show the whole board). Prints
each image's reprojection RMS (or "board not found"), the overall RMS and the intrinsics,
and writes them as OpenCV FileStorage YAML (camera_matrix, distortion_coefficients,
image_width, image_height), the format --calib reads.)");
    addRequired(*c, "--images", o.images, "DIR", "folder of board photos, used in name order");
    // "9x6": each side 3..100 inner corners.
    const auto board = [&o](const std::string& text) {
        const auto side = [&text](const std::string& part) {
            const std::optional<long> value = parseInteger(part);
            if (!value)
                throw CLI::ValidationError("--board", "'" + text + "' is not COLSxROWS (inner corners, e.g. 9x6)");
            if (*value < 3 || *value > 100)
                throw CLI::ValidationError("--board", text + ": each side needs 3..100 inner corners");
            return int(*value);
        };
        const size_t x = text.find_first_of("xX");
        if (x == std::string::npos)
            throw CLI::ValidationError("--board", "'" + text + "' is not COLSxROWS (inner corners, e.g. 9x6)");
        o.boardColumns = side(text.substr(0, x));
        o.boardRows = side(text.substr(x + 1));
    };
    c->add_option_function<std::string>("--board", board,
                                        "inner corners (where four squares meet), e.g. 9x6 for 10x7 squares")
        ->type_name("COLSxROWS")
        ->required();
    addDouble(*c, "--square", o.square, {0, 1000, true}, "S",
              "side of one square in metres (scales the board poses only)")
        ->required()
        ->default_str("");
    addRequired(*c, "--out", o.out, "FILE", "calibration file to write");
    addLogLevel(*c, o.logLevel);
    return {c, [&o] { return calibrateCommand(o); }};
}

Command declareMarkers(CLI::App& lumar, MarkersCommandOptions& o)
{
    CLI::App* c = lumar.add_subcommand(
        "markers", R"(printable AprilTags at their exact size (PDF, PNG or SVG), and boards as [[maps]]

Lays the tags out on A4 or Letter pages at their physical size: --size is the side the
detector measures, as [[markers]] size means it (for tag36h11 the black square, border to
border). Each tag has its id, family and size printed under it, and every page a 10 cm
scale bar to check that the printer did not scale the page. With --board the tags form one
multi-tag map, filled row by row from the top left, and its [[maps]] entry is written as a
configuration file (map origin at the board's centre, x right, y up the page).)");
    c->add_option("--family", o.family, "tag family")->type_name("NAME")->capture_default_str();
    addRequired(*c, "--ids", o.ids, "LIST", "ids and ranges, e.g. 0-3 or 0,2,5-7");
    addDouble(*c, "--size", o.size, {0, 10, true}, "M", "tag side in metres, black border to black border")
        ->required()
        ->default_str("");
    addRequired(*c, "--out", o.out, "FILE", "file.pdf, file.png or file.svg (PNG and SVG: one file a page)");
    c->add_option("--page", o.page, "paper: a4 or letter")->type_name("PAPER")->capture_default_str();
    addInteger(*c, "--dpi", o.dpi, {36, 2400}, "PNG resolution in pixels per inch");
    c->add_option("--board", o.board, "one board of ROWSxCOLS tags (a [[maps]] entry)")->type_name("ROWSxCOLS");
    c->add_option_function<double>(
         "--spacing", [&o](double v) { o.spacing = v; },
         "board: metres between neighbouring tags' borders (default: their white rings)")
        ->type_name("M");
    c->add_option("--map-name", o.mapName, "board: the [[maps]] name")->type_name("NAME")->capture_default_str();
    c->add_option_function<std::string>(
         "--map-out", [&o](const std::string& v) { o.mapOut = v; }, "board: the map file (default: --out as .toml)")
        ->type_name("FILE");
    addLogLevel(*c, o.logLevel);
    return {c, [&o] { return markersCommand(o); }};
}

// ---- Parsing and exit codes -------------------------------------------------------------

// One line, naming the command and where its options are explained.
int usageError(const std::string& command, const std::string& what)
{
    const std::string prefix = command.empty() ? "lumar" : "lumar " + command;
    std::fprintf(stderr, "%s: %s (see '%s --help')\n", prefix.c_str(), what.c_str(), prefix.c_str());
    return kExitBadInput;
}

int parseAndRun(const std::vector<std::string>& args)
{
    CLI::App lumar(R"(lumar: photorealistic AR for embedded Linux

Run 'lumar <command> --help' for a command's options.)",
                   "lumar");
    lumar.formatter(std::make_shared<HelpFormatter>());
    lumar.option_defaults()->group("options"); // commands inherit it, and the help flag
    lumar.set_help_flag("-h,--help", "print this help and exit");
    lumar.require_subcommand(1);

    Options options;
    const Command commands[] = {
        declareRender(lumar, options.render),
        declareRun(lumar, options.run),
        declareCheckConfig(lumar, options.checkConfig),
        declareDetect(lumar, options.detect),
        declareBench(lumar, options.bench),
        declareProbe(lumar, options.probe),
        declareCalibrate(lumar, options.calibrate),
        declareMarkers(lumar, options.markers),
    };
    for (const Command& command : commands) {
        command.app->group("commands");
        command.app->get_help_ptr()->group("options");
    }

    // The command line's first word names the command (CLI11 would report a misspelt one as
    // a missing command); "lumar help" is "lumar --help".
    std::string name = args.empty() ? "" : args.front();
    const bool known = std::any_of(std::begin(commands), std::end(commands),
                                   [&name](const Command& c) { return c.app->get_name() == name; });
    if (name == "help")
        return parseAndRun({"--help"});
    if (!known && !name.empty() && name.front() != '-')
        return usageError("", "unknown command '" + name + "'");
    if (!known)
        name.clear();
    // The tracking benchmark has its own options (tracking_bench_command.cpp).
    if (name == "bench" && std::find(args.begin(), args.end(), "--tracking") != args.end())
        return trackingBenchCommand({args.begin() + 1, args.end()});

    // --help wins over any mistake beside it (CLI11 would check the values first).
    if (std::find_if(args.begin(), args.end(), [](const std::string& a) { return a == "-h" || a == "--help"; }) !=
        args.end()) {
        std::fputs((name.empty() ? lumar.help() : lumar.get_subcommand(name)->help("lumar")).c_str(), stdout);
        return kExitOk;
    }
    try {
        // CLI11 takes the arguments in reverse order.
        lumar.parse(std::vector<std::string>(args.rbegin(), args.rend()));
    } catch (const CLI::ParseError& e) {
        // CLI11 checks required options before unknown ones; the unknown one is the mistake
        // to name ("--fraems 3" is reported as such, not as a missing --frames).
        const std::vector<std::string> unknown = (name.empty() ? &lumar : lumar.get_subcommand(name))->remaining();
        if (!unknown.empty())
            return usageError(name, unknown.front().front() == '-' ? "unknown option " + unknown.front()
                                                                   : "unexpected argument '" + unknown.front() + "'");
        return usageError(name, name.empty() && e.get_name() == "RequiredError" ? "no command given" : e.what());
    }
    for (const Command& command : commands)
        if (command.app->parsed())
            return command.run();
    return usageError("", "no command given");
}

} // namespace

int lumarMain(const std::vector<std::string>& args)
{
    const std::string command = args.empty() ? "" : args.front();
    try {
        return parseAndRun(args);
    } catch (const UsageError& e) {
        return usageError(command, e.what());
    } catch (const InputError& e) {
        std::fprintf(stderr, "lumar: %s\n", e.what());
        return kExitBadInput;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "lumar: %s\n", e.what());
        return kExitRuntime;
    }
}

} // namespace lumar
