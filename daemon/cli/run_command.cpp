// lumar run: the daemon loop. Frames are processed as the camera delivers them (file and fake
// sources are paced to their frame rate), the headless sink keeps the output file current,
// and SIGINT/SIGTERM stop the loop cleanly after the frame in flight.
#include <array>
#include <atomic>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <filesystem>
#include <optional>
#include <thread>

#include "capture/reconnecting_source.h"
#include "command_line.h"
#include "commands.h"
#include "config/config.h"
#include "config_watcher.h"
#include "core/error.h"
#include "core/log.h"
#include "output/frame_writer.h"
#include "pipeline.h"
#include "service_notifier.h"
#include "status_file.h"

namespace lumar {
namespace {

constexpr const char* kHelp = R"(usage: lumar run [--config FILE] [--frames N] [--log-level SPEC]

Runs the AR pipeline continuously until SIGINT or SIGTERM (or N frames when --frames is
given). The output goes to the configured sink: [output] path = "x.png" keeps a still of
the newest frame (rewritten once a second, atomically), "x.y4m" records every frame.

The configuration file is reloaded when it changes on disk (editors and mv included) or on
SIGHUP; a file with an error is rejected with its FILE:LINE message and the last good
configuration keeps running. Under systemd (Type=notify) it reports READY=1 after the first
frame, WATCHDOG=1 while frames flow, and STATUS= with fps and tracking state.
)";

std::atomic<bool> gStopRequested{false};
std::atomic<bool> gReloadRequested{false};

extern "C" void onSignal(int signal)
{
    if (signal == SIGHUP)
        gReloadRequested.store(true);
    else
        gStopRequested.store(true);
}

// Installs the stop and reload handlers for the lifetime of the loop and restores the old
// ones after.
class LoopSignals {
public:
    LoopSignals()
    {
        struct sigaction action {};
        action.sa_handler = onSignal;
        sigemptyset(&action.sa_mask);
        for (size_t i = 0; i < kSignals.size(); ++i)
            sigaction(kSignals[i], &action, &old_[i]);
    }
    ~LoopSignals()
    {
        for (size_t i = 0; i < kSignals.size(); ++i)
            sigaction(kSignals[i], &old_[i], nullptr);
    }
    LoopSignals(const LoopSignals&) = delete;
    LoopSignals& operator=(const LoopSignals&) = delete;

private:
    static constexpr std::array<int, 3> kSignals{SIGINT, SIGTERM, SIGHUP};
    std::array<struct sigaction, 3> old_{};
};

// The headless sink of `run`: a still refreshed periodically, or a video of every frame.
class HeadlessSink {
public:
    HeadlessSink(const OutputConfig& output, double fps) : path_(output.path)
    {
        if (output.sink == "none" || path_.empty())
            return;
        if (path_.extension() == ".y4m")
            video_ = openFrameWriter(path_, fps);
    }
    void present(const Image8& frame, std::chrono::steady_clock::time_point now)
    {
        if (video_) {
            video_->write(frame);
        } else if (!path_.empty() && now >= nextStill_) {
            // Write beside the target and rename, so a reader never sees a half-written file.
            const std::filesystem::path partial = path_.string() + ".partial.png";
            writePng(partial, frame);
            std::filesystem::rename(partial, path_);
            nextStill_ = now + std::chrono::seconds(1);
        }
    }
    void finish(const Image8& last)
    {
        if (video_)
            video_->finish();
        else if (!path_.empty() && !last.empty())
            present(last, std::chrono::steady_clock::time_point::max());
    }

private:
    std::filesystem::path path_;
    std::unique_ptr<FrameWriter> video_;
    std::chrono::steady_clock::time_point nextStill_{};
};

// Everything a configuration builds; replaced as a whole when a new one is accepted.
struct RunningScene {
    std::unique_ptr<Pipeline> pipeline;
    std::unique_ptr<HeadlessSink> sink;
    StatusFile statusFile;

    explicit RunningScene(const Config& config)
        : pipeline(std::make_unique<Pipeline>(config)),
          sink(std::make_unique<HeadlessSink>(config.output, pipeline->fps())), statusFile(config.output.statusPath)
    {
        // The daemon renders every frame without waiting for detection.
        pipeline->detectInBackground();
    }
};

// Parse → validate → build, all before anything running is touched: a bad file (or a model
// it names) leaves the current scene running. Returns false when the new file was rejected.
bool reload(const std::filesystem::path& file, std::unique_ptr<RunningScene>& scene, ServiceNotifier& notifier,
            RunStatus& status)
{
    notifier.reloading();
    try {
        const Config config = loadConfig(file);
        auto next = std::make_unique<RunningScene>(config);
        scene->sink->finish(scene->pipeline->output());
        scene = std::move(next);
        log::configure(config.logLevel);
        LUMAR_LOG(Config, Info) << "reloaded " << file.string();
        status.config = "ok";
        notifier.ready();
        return true;
    } catch (const InputError& e) {
        LUMAR_LOG(Config, Error) << "configuration rejected, keeping the last good one: " << e.what();
        notifier.status(std::string("configuration rejected: ") + e.what());
        status.config = std::string("rejected: ") + e.what();
        notifier.ready();
        return false;
    }
}

} // namespace

int runCommand(const Args& args)
{
    const CommandLine cl(args, {{"config"}, {"frames"}, {"log-level"}});
    if (cl.helpRequested()) {
        std::fputs(kHelp, stdout);
        return kExitOk;
    }
    if (!cl.positional().empty())
        throw UsageError("unexpected argument '" + cl.positional().front() + "'");
    const long maxFrames = cl.integer("frames", 0, 0, 1L << 40);

    const Config config = configFromCommandLine(cl);
    auto scene = std::make_unique<RunningScene>(config);
    const auto configFile = cl.value("config");
    std::optional<ConfigWatcher> watcher;
    if (configFile)
        watcher.emplace(*configFile);
    ServiceNotifier notifier;
    LoopSignals signals;
    gStopRequested.store(false);
    gReloadRequested.store(false);

    using Clock = std::chrono::steady_clock;
    auto frameInterval = [&] {
        return std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(1.0 / scene->pipeline->fps()));
    };
    auto paceStart = Clock::now();
    long paceFrames = 0;
    // Every second the status file is rewritten; every fifth, systemd's STATUS= and the log.
    const auto started = paceStart;
    auto windowStart = paceStart;
    long frames = 0, framesInWindow = 0, withMarker = 0, windows = 0;
    RunStatus status;
    FrameReport report;
    LUMAR_LOG(App, Info) << "running at " << scene->pipeline->fps() << " fps; SIGINT or SIGTERM stops, SIGHUP reloads";

    while (!gStopRequested.load() && (maxFrames == 0 || frames < maxFrames)) {
        if (configFile && (gReloadRequested.exchange(false) || watcher->changed())) {
            if (reload(*configFile, scene, notifier, status)) {
                paceStart = Clock::now();
                paceFrames = 0;
            }
        }
        try {
            if (!scene->pipeline->step(report))
                break;
        } catch (const InputError& e) {
            // A corrupt frame from a file source: report it and keep showing the last good one.
            LUMAR_LOG(Capture, Error) << e.what();
            continue;
        } catch (const CameraUnavailable& e) {
            // Unplugged or hung: the capture thread is reopening it with backoff; the last
            // frame stays on the output meanwhile.
            notifier.status(std::string("camera unavailable: ") + e.what());
            status.camera = std::string("unavailable: ") + e.what();
            continue;
        }
        ++frames;
        ++paceFrames;
        ++framesInWindow;
        withMarker += report.detections.empty() ? 0 : 1;
        status.camera = "ok";
        const auto now = Clock::now();
        scene->sink->present(scene->pipeline->output(), now);
        notifier.frameDone(now);
        if (now - windowStart >= std::chrono::seconds(1)) {
            status.fps = double(framesInWindow) / std::chrono::duration<double>(now - windowStart).count();
            status.frames = frames;
            status.framesWithMarkers = withMarker;
            status.objectsDrawn = report.objectsDrawn;
            status.markersVisible.clear();
            for (const TagDetection& d : report.detections)
                status.markersVisible.push_back(d.id);
            status.uptimeS = std::chrono::duration<double>(now - started).count();
            scene->statusFile.write(status);
            if (++windows % 5 == 0) {
                char line[160];
                std::snprintf(line, sizeof line, "%.1f fps, markers in %ld/%ld frames, %d object(s) drawn", status.fps,
                              withMarker, frames, report.objectsDrawn);
                LUMAR_LOG(App, Info) << "status: " << line;
                notifier.status(line);
            }
            framesInWindow = 0;
            windowStart = now;
        }
        std::this_thread::sleep_until(paceStart + paceFrames * frameInterval());
    }
    notifier.stopping();
    scene->sink->finish(scene->pipeline->output());
    LUMAR_LOG(App, Info) << "stopped after " << frames << " frames";
    return kExitOk;
}

} // namespace lumar
