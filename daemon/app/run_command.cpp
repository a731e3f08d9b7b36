// lumar run: the daemon loop. Frames are processed as the camera delivers them (file and fake
// sources are paced to their frame rate), the headless sink keeps the output file current,
// and SIGINT/SIGTERM stop the loop cleanly after the frame in flight.
#include <atomic>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <filesystem>
#include <thread>

#include "command_line.h"
#include "commands.h"
#include "config/config.h"
#include "core/error.h"
#include "core/log.h"
#include "output/frame_writer.h"
#include "pipeline.h"

namespace lumar {
namespace {

constexpr const char* kHelp = R"(usage: lumar run [--config FILE] [--frames N] [--log-level SPEC]

Runs the AR pipeline continuously until SIGINT or SIGTERM (or N frames when --frames is
given). The output goes to the configured sink: [output] path = "x.png" keeps a still of
the newest frame (rewritten once a second, atomically), "x.y4m" records every frame.
)";

std::atomic<bool> gStopRequested{false};

extern "C" void requestStop(int /*signal*/)
{
    gStopRequested.store(true);
}

// Installs the stop handlers for the lifetime of the loop and restores the old ones after.
class StopSignals {
public:
    StopSignals()
    {
        struct sigaction action {};
        action.sa_handler = requestStop;
        sigemptyset(&action.sa_mask);
        sigaction(SIGINT, &action, &oldInt_);
        sigaction(SIGTERM, &action, &oldTerm_);
    }
    ~StopSignals()
    {
        sigaction(SIGINT, &oldInt_, nullptr);
        sigaction(SIGTERM, &oldTerm_, nullptr);
    }
    StopSignals(const StopSignals&) = delete;
    StopSignals& operator=(const StopSignals&) = delete;

private:
    struct sigaction oldInt_ {};
    struct sigaction oldTerm_ {};
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
    Pipeline pipeline(config);
    HeadlessSink sink(config.output, pipeline.fps());
    StopSignals signals;
    gStopRequested.store(false);

    using Clock = std::chrono::steady_clock;
    const auto frameInterval = std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(1.0 / pipeline.fps()));
    const auto start = Clock::now();
    auto nextStatus = start + std::chrono::seconds(5);
    long frames = 0, framesSinceStatus = 0, withMarker = 0;
    FrameReport report;
    LUMAR_LOG(App, Info) << "running at " << pipeline.fps() << " fps; SIGINT or SIGTERM stops";

    while (!gStopRequested.load() && (maxFrames == 0 || frames < maxFrames)) {
        try {
            if (!pipeline.step(report))
                break;
        } catch (const InputError& e) {
            // A corrupt frame from a file source: report it and keep showing the last good one.
            LUMAR_LOG(Capture, Error) << e.what();
            continue;
        }
        ++frames;
        ++framesSinceStatus;
        withMarker += report.detections.empty() ? 0 : 1;
        const auto now = Clock::now();
        sink.present(pipeline.output(), now);
        if (now >= nextStatus) {
            const double seconds = std::chrono::duration<double>(now - (nextStatus - std::chrono::seconds(5))).count();
            LUMAR_LOG(App, Info) << "status: " << framesSinceStatus / seconds << " fps, markers in " << withMarker << "/"
                                 << frames << " frames";
            framesSinceStatus = 0;
            nextStatus = now + std::chrono::seconds(5);
        }
        std::this_thread::sleep_until(start + frames * frameInterval);
    }
    sink.finish(pipeline.output());
    LUMAR_LOG(App, Info) << "stopped after " << frames << " frames";
    return kExitOk;
}

} // namespace lumar
