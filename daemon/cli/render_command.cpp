// lumar render: N frames through the whole pipeline, offline and deterministic (a fake or
// file source is played frame by frame with no pacing), to PNG and/or Y4M files.
#include <chrono>
#include <cstdio>
#include <optional>

#include "capture/reconnecting_source.h"
#include "command_line.h"
#include "commands.h"
#include "config/config.h"
#include "core/error.h"
#include "core/log.h"
#include "frame_trace.h"
#include "numbered_png_writer.h"
#include "output/frame_writer.h"
#include "pipeline.h"

namespace lumar {
namespace {

constexpr const char* kHelp = R"(usage: lumar render [--config FILE] [--frames N] --out FILE [--out FILE ...]
                    [--trace FILE] [--log-level SPEC]

Renders N frames (default 30) of the configured scene and writes them:
  --out out.png   the last frame as a PNG still
  --out out.y4m   every frame as Y4M video (4:2:0, full range)
  --out f_%04d.png  every frame as its own PNG
  --trace FILE    one JSON line per frame: detections, poses, stage times
Without --config the built-in default runs: fake camera, demo model, HDR environment.
)";

} // namespace

int renderCommand(const Args& args)
{
    const CommandLine cl(args, {{"config"}, {"frames"}, {"out", true, true}, {"trace"}, {"log-level"}});
    if (cl.helpRequested()) {
        std::fputs(kHelp, stdout);
        return kExitOk;
    }
    if (!cl.positional().empty())
        throw UsageError("unexpected argument '" + cl.positional().front() + "'");
    const auto outputs = cl.values("out");
    if (outputs.empty())
        throw UsageError("--out FILE is required (.png or .y4m)");
    const long frames = cl.integer("frames", 30, 1, 1000000);

    const Config config = configFromCommandLine(cl);
    Pipeline pipeline(config);
    std::vector<std::unique_ptr<FrameWriter>> writers;
    writers.reserve(outputs.size());
    for (const std::string& out : outputs)
        writers.push_back(NumberedPngWriter::isPattern(out) ? std::make_unique<NumberedPngWriter>(out)
                                                            : openFrameWriter(out, pipeline.fps()));
    std::optional<FrameTrace> trace;
    if (const auto file = cl.value("trace"))
        trace.emplace(*file);

    FrameReport report;
    long rendered = 0, withMarker = 0;
    const auto start = std::chrono::steady_clock::now();
    // An offline render waits for a lost camera, but not forever.
    constexpr auto kCameraGiveUp = std::chrono::seconds(10);
    auto cameraLostSince = std::chrono::steady_clock::time_point::max();
    for (;;) {
        try {
            if (rendered >= frames || !pipeline.step(report))
                break;
            cameraLostSince = std::chrono::steady_clock::time_point::max();
        } catch (const CameraUnavailable&) {
            const auto now = std::chrono::steady_clock::now();
            cameraLostSince = std::min(cameraLostSince, now);
            if (now - cameraLostSince > kCameraGiveUp)
                throw;
            continue;
        }
        ++rendered;
        withMarker += report.detections.empty() ? 0 : 1;
        for (auto& writer : writers)
            writer->write(pipeline.output());
        if (trace)
            trace->write(report);
    }
    for (auto& writer : writers)
        writer->finish();
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();

    std::printf("rendered %ld frames at %dx%d in %.2f s (%.1f fps); markers found in %ld of %ld frames\n", rendered,
                pipeline.output().width, pipeline.output().height, seconds, seconds > 0 ? rendered / seconds : 0.0,
                withMarker, rendered);
    for (const std::string& out : outputs)
        std::printf("wrote %s\n", out.c_str());
    return kExitOk;
}

} // namespace lumar
