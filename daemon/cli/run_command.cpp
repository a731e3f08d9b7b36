// lumar run: the daemon loop. Frames are processed as the camera delivers them (file and fake
// sources are paced to their frame rate), the headless sink keeps the output file current,
// and SIGINT/SIGTERM stop the loop cleanly after the frame in flight.
#include <algorithm>
#include <array>
#include <atomic>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <filesystem>
#include <optional>
#include <thread>
#include <utility>

#include "capture/reconnecting_source.h"
#include "commands.h"
#include "config/config.h"
#include "config_watcher.h"
#include "core/error.h"
#include "core/log.h"
#include "gles_renderer/gl/gl_census.h"
#include "kms_sink.h"
#include "latency_window.h"
#include "output/frame_writer.h"
#include "pipeline.h"
#include "process_clock.h"
#include "service_notifier.h"
#include "status_file.h"
#include "window_sink.h"

namespace lumar {
namespace {

std::atomic<bool> gStopRequested{false};
std::atomic<bool> gReloadRequested{false};

extern "C" void onSignal(int signal)
{
    if (signal == SIGHUP)
        gReloadRequested.store(true);
    else
        gStopRequested.store(true);
}

// Waits for the next frame's time, or less: a stop or reload signal ends the wait within a
// slice (issue 16: a slow frame rate kept `lumar run` asleep, deaf to SIGTERM, until systemd's
// SIGKILL). Slices rather than one interruptible sleep, because the signal may be delivered
// to any of the process's threads and interrupt none of this one's calls.
void sleepUntilSignalled(std::chrono::steady_clock::time_point deadline)
{
    constexpr auto kSlice = std::chrono::milliseconds(20);
    while (!gStopRequested.load() && !gReloadRequested.load()) {
        const auto now = std::chrono::steady_clock::now();
        if (now >= deadline)
            return;
        std::this_thread::sleep_for(std::min<std::chrono::steady_clock::duration>(deadline - now, kSlice));
    }
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
        // A peer that went away (the preview window's X server, a status reader's socket)
        // must be an EPIPE the code reports, not a signal that kills the daemon.
        struct sigaction ignore {};
        ignore.sa_handler = SIG_IGN;
        sigemptyset(&ignore.sa_mask);
        sigaction(SIGPIPE, &ignore, &oldPipe_);
    }
    ~LoopSignals()
    {
        for (size_t i = 0; i < kSignals.size(); ++i)
            sigaction(kSignals[i], &old_[i], nullptr);
        sigaction(SIGPIPE, &oldPipe_, nullptr);
    }
    LoopSignals(const LoopSignals&) = delete;
    LoopSignals& operator=(const LoopSignals&) = delete;

private:
    static constexpr std::array<int, 3> kSignals{SIGINT, SIGTERM, SIGHUP};
    std::array<struct sigaction, 3> old_{};
    struct sigaction oldPipe_ {};
};

// The headless sink of `run`: a still refreshed periodically, or a video of every frame. With
// a KMS display it writes nothing (the frames are not read back); when `sink = "kms"` found
// no display it is the fallback.
class HeadlessSink {
public:
    HeadlessSink(const OutputConfig& output, double fps, const WindowTarget* display) : path_(output.path)
    {
        if (output.sink == "none" || display)
            path_.clear();
        if (path_.empty())
            return;
        if (path_.extension() == ".y4m")
            video_ = openFrameWriter(path_, fps);
    }
    void present(const Image8& frame, std::chrono::steady_clock::time_point now)
    {
        if (video_) {
            video_->write(frame);
        } else if (!path_.empty() && now >= nextStill_) {
            writeStill(frame);
            nextStill_ = now + std::chrono::seconds(1);
        }
    }
    void finish(const Image8& last)
    {
        if (video_)
            video_->finish();
        else if (!path_.empty() && !last.empty())
            writeStill(last);
    }

private:
    // Beside the target, then renamed: a reader never sees a half-written file.
    void writeStill(const Image8& frame)
    {
        const std::filesystem::path partial = path_.string() + ".partial.png";
        writePng(partial, frame);
        std::filesystem::rename(partial, path_);
    }

    std::filesystem::path path_;
    std::unique_ptr<FrameWriter> video_;
    std::chrono::steady_clock::time_point nextStill_{};
};

// The run loop's part of the setup view's status line (app/setup_overlay.h).
std::string overlayStatus(const RunStatus& status)
{
    char line[160];
    std::snprintf(line, sizeof line, "%.1f fps  latency p50 %.0f ms  camera %s", status.fps,
                  status.latencyP50Ms.value_or(0.0), status.camera.c_str());
    return line;
}

// Everything a configuration builds; updated in place by a reload that keeps the camera,
// replaced as a whole by one that does not.
// The KMS display or the preview window (`display`) is opened once per process and outlives
// every scene: a reload keeps its mode and plane, or the window.
struct RunningScene {
    WindowTarget* display;
    std::unique_ptr<Pipeline> pipeline;
    std::unique_ptr<HeadlessSink> sink;
    StatusFile statusFile;
    OutputConfig output; // what sink and statusFile were made from

    RunningScene(const Config& config, WindowTarget* kms)
        : display(kms), pipeline(std::make_unique<Pipeline>(config, false, kms, 0, true)),
          sink(std::make_unique<HeadlessSink>(config.output, pipeline->fps(), kms)),
          statusFile(config.output.statusPath), output(config.output)
    {
        // The daemon renders every frame without waiting for detection.
        pipeline->detectInBackground();
    }
};

// What a reload in place kept and what it made anew, for the log.
std::string describe(const ReloadSummary& summary)
{
    std::string kept = "camera", made;
    const auto add = [](std::string& list, const char* part) {
        list += (list.empty() ? "" : ", ") + std::string(part);
    };
    add(summary.keptRenderer ? kept : made, "GL context");
    add(summary.keptTracker ? kept : made, "tracker");
    add(summary.keptEnvironment ? kept : made, "environment map");
    return "kept " + kept + (made.empty() ? "" : "; new " + made) + "; models " + std::to_string(summary.modelsBefore) +
           " → " + std::to_string(summary.modelsAfter);
}

// Parse → validate → load, all before anything running is touched: a bad file (or a model it
// names) leaves the current scene running. The camera and the GL context are kept where the
// new file allows it (Pipeline::prepareReload); a [camera] change builds a new scene.
// Returns false when the new file was rejected.
bool reload(const std::filesystem::path& file, std::unique_ptr<RunningScene>& scene, ServiceNotifier& notifier,
            RunStatus& status)
{
    const auto start = std::chrono::steady_clock::now();
    notifier.reloading();
    try {
        const Config config = loadConfig(file);
        const auto onScreen = [](const std::string& sink) { return sink == "kms" || sink == "window"; };
        if (config.output.sink != scene->output.sink && (onScreen(config.output.sink) || onScreen(scene->output.sink)))
            LUMAR_LOG(Output, Warn) << "output.sink changed to \"" << config.output.sink
                                    << "\": the display is chosen at start-up, restart lumar to switch";
        std::string what;
        if (scene->pipeline->keepsCamera(config)) {
            Pipeline::PreparedReload prepared = scene->pipeline->prepareReload(config);
            std::unique_ptr<HeadlessSink> sink;
            if (config.output != scene->output)
                sink = std::make_unique<HeadlessSink>(config.output, scene->pipeline->fps(), scene->display);
            // Nothing left that bad input can fail.
            what = describe(scene->pipeline->applyReload(std::move(prepared)));
            if (sink) {
                scene->sink->finish(scene->pipeline->output());
                scene->sink = std::move(sink);
            }
            scene->statusFile = StatusFile(config.output.statusPath);
            scene->output = config.output;
        } else {
            auto next = std::make_unique<RunningScene>(config, scene->display);
            scene->sink->finish(scene->pipeline->output());
            scene = std::move(next);
            what = "new camera, GL context and everything else ([camera] changed)";
        }
        status.lastReloadMs =
            std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
        log::configure(config.logLevel);
        char ms[32];
        std::snprintf(ms, sizeof ms, "%.1f", *status.lastReloadMs);
        LUMAR_LOG(Config, Info) << "reloaded " << file.string() << " in " << ms << " ms: " << what;
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

int runCommand(const RunCommandOptions& options)
{
    const long maxFrames = options.frames;
    const auto commandStarted = std::chrono::steady_clock::now(); // start-up's fallback origin

    Config config = configFromOptions(options.config);
    if (options.overlay)
        config.output.overlay = true;
    // Declared before the scene: its renderers draw on the display's EGL display.
    std::unique_ptr<KmsDisplay> kms;
    std::unique_ptr<PreviewWindow> window;
    if (config.output.sink == "kms" && !options.preview)
        kms = openKmsDisplay(config);
    else if (config.output.sink == "window" || options.preview)
        window = openPreviewWindow(config);
    WindowTarget* display = kms ? static_cast<WindowTarget*>(kms.get()) : window.get();
    auto scene = std::make_unique<RunningScene>(config, display);
    const std::optional<std::string>& configFile = options.config.file;
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
    LatencyWindow latency;
    bool cameraDown = false; // since a CameraUnavailable, until the next frame
    auto statusLine = [&] {
        char line[160];
        std::snprintf(line, sizeof line, "%.1f fps, markers in %ld/%ld frames, %d object(s) drawn", status.fps,
                      withMarker, frames, report.objectsDrawn);
        return std::string(line);
    };
    LUMAR_LOG(App, Info) << "running at " << scene->pipeline->fps() << " fps; SIGINT or SIGTERM stops, SIGHUP reloads";

    std::pair<int, int> windowFrame{0, 0}; // the frame size the window was last fitted to
    while (!gStopRequested.load() && (maxFrames == 0 || frames < maxFrames)) {
        // Closing the preview window ends the run as a stop signal does.
        if (window) {
            // Sized for the camera's frames at the start and after a camera change.
            const CameraIntrinsics& frame = scene->pipeline->intrinsics();
            if (std::pair(frame.width, frame.height) != windowFrame) {
                windowFrame = {frame.width, frame.height};
                window->fitFrame(frame.width, frame.height);
            }
            window->pollEvents();
            // The key o turns the setup view on and off; q or Escape ends the run as closing
            // the window does: lumar draws no decorations, and some compositors (weston's
            // shells) have no other way to close a window.
            bool quitKey = false;
            for (const char key : window->takeTypedKeys()) {
                if (key == 'o' || key == 'O')
                    scene->pipeline->setOverlay(!scene->pipeline->overlay());
                quitKey = quitKey || key == 'q' || key == 'Q' || key == '\x1b';
            }
            if (quitKey || window->closeRequested()) {
                LUMAR_LOG(App, Info) << (quitKey ? "the preview window's quit key was pressed"
                                                 : "the preview window was closed");
                break;
            }
        }
        // Both sources are drained every frame: an edit followed by `systemctl reload` within
        // the same frame reloads once, not twice.
        const bool hangUp = gReloadRequested.exchange(false);
        const bool edited = configFile && watcher->changed();
        if (configFile && (hangUp || edited)) {
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
            // No frame comes, so neither does the periodic rewrite below: say it now.
            status.uptimeS = std::chrono::duration<double>(Clock::now() - started).count();
            scene->statusFile.writeOrReport(status);
            cameraDown = true;
            continue;
        }
        ++frames;
        ++paceFrames;
        ++framesInWindow;
        withMarker += report.detections.empty() ? 0 : 1;
        if (report.latencyMs)
            latency.add(*report.latencyMs);
        status.camera = "ok";
        const auto now = Clock::now();
        scene->sink->present(scene->pipeline->output(), now);
        if (!status.startupMs) {
            // From the process's creation when /proc tells it (10 ms ticks), else from here.
            const std::optional<double> sinceProcessStart = millisecondsSinceProcessStart();
            status.startupMs = sinceProcessStart.value_or(
                std::chrono::duration<double, std::milli>(Clock::now() - commandStarted).count());
            char ms[32];
            std::snprintf(ms, sizeof ms, "%.0f", *status.startupMs);
            LUMAR_LOG(App, Info) << "first frame presented " << ms << " ms after the "
                                 << (sinceProcessStart ? "process started" : "command started");
            // systemd shows a status from READY on, not only after the first frame-rate window.
            notifier.status(std::string("first frame presented after ") + ms + " ms");
        }
        notifier.frameDone(now);
        if (std::exchange(cameraDown, false)) {
            // Back: both reports lose the "unavailable" at once, not at the next window.
            status.uptimeS = std::chrono::duration<double>(now - started).count();
            scene->statusFile.writeOrReport(status);
            notifier.status(statusLine());
        }
        if (now - windowStart >= std::chrono::seconds(1)) {
            status.fps = double(framesInWindow) / std::chrono::duration<double>(now - windowStart).count();
            status.frames = frames;
            status.framesWithMarkers = withMarker;
            status.objectsDrawn = report.objectsDrawn;
            status.latencyP50Ms = latency.percentile(0.5);
            status.latencyP99Ms = latency.percentile(0.99);
            status.framesDropped = scene->pipeline->framesDropped();
            status.glObjects = glObjectCensus();
            status.markersVisible.clear();
            for (const TagDetection& d : report.detections)
                status.markersVisible.push_back(d.id);
            status.uptimeS = std::chrono::duration<double>(now - started).count();
            scene->statusFile.writeOrReport(status);
            scene->pipeline->setOverlayStatus(overlayStatus(status));
            if (++windows % 5 == 0) {
                const std::string line = statusLine();
                LUMAR_LOG(App, Info) << "status: " << line;
                notifier.status(line);
            }
            framesInWindow = 0;
            windowStart = now;
        }
        // A camera paces the loop itself: next() waits for its newest frame.
        if (!scene->pipeline->capturePacesItself())
            sleepUntilSignalled(paceStart + paceFrames * frameInterval());
    }
    notifier.stopping();
    scene->sink->finish(scene->pipeline->output());
    LUMAR_LOG(App, Info) << "stopped after " << frames << " frames";
    return kExitOk;
}

} // namespace lumar
