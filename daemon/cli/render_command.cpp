// lumar render: N frames through the whole pipeline, offline and deterministic (a fake or
// file source is played frame by frame with no pacing), to PNG and/or Y4M files.
#include <chrono>
#include <cstdio>
#include <optional>

#include "capture/reconnecting_source.h"
#include "commands.h"
#include "config/config.h"
#include "core/error.h"
#include "core/log.h"
#include "frame_trace.h"
#include "numbered_png_writer.h"
#include "output/frame_writer.h"
#include "pipeline.h"

namespace lumar {

int renderCommand(const RenderCommandOptions& options)
{
    const Config config = configFromOptions(options.config);
    Pipeline pipeline(config);
    std::vector<std::unique_ptr<FrameWriter>> writers;
    writers.reserve(options.outputs.size());
    for (const std::string& out : options.outputs)
        writers.push_back(NumberedPngWriter::isPattern(out) ? std::make_unique<NumberedPngWriter>(out)
                                                            : openFrameWriter(out, pipeline.fps()));
    std::optional<FrameTrace> trace;
    if (options.trace)
        trace.emplace(*options.trace);

    FrameReport report;
    long rendered = 0, withMarker = 0;
    const auto start = std::chrono::steady_clock::now();
    // An offline render waits for a lost camera, but not forever.
    constexpr auto kCameraGiveUp = std::chrono::seconds(10);
    auto cameraLostSince = std::chrono::steady_clock::time_point::max();
    for (;;) {
        try {
            if (rendered >= options.frames || !pipeline.step(report))
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
    for (const std::string& out : options.outputs)
        std::printf("wrote %s\n", out.c_str());
    return kExitOk;
}

} // namespace lumar
