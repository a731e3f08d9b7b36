// lumar bench: runs the pipeline as fast as it goes (no pacing, no output files) and reports
// frame-time percentiles, mean per-stage times and memory. Timings are measured here, never
// asserted in tests (DESIGN.md §9).
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <ctime>
#include <fstream>
#include <iterator>
#include <string>
#include <thread>
#include <vector>

#include <malloc.h>
#if defined(__SANITIZE_ADDRESS__)
// AddressSanitizer's allocator statistics (compiler-rt's sanitizer/allocator_interface.h, which
// GCC does not install; libasan exports them).
extern "C" size_t __sanitizer_get_current_allocated_bytes();
extern "C" size_t __sanitizer_get_heap_size();
#endif

#include "capture/replay_source.h"
#include "commands.h"
#include "config/config.h"
#include "core/error.h"
#include "core/json_output.h"
#include "pipeline.h"

namespace lumar {
namespace {

double percentile(std::vector<double> values, double p)
{
    if (values.empty())
        return 0.0;
    std::sort(values.begin(), values.end());
    const size_t index = std::min(values.size() - 1, size_t(p * double(values.size() - 1) + 0.5));
    return values[index];
}

double mean(const std::vector<double>& values)
{
    double sum = 0;
    for (double v : values)
        sum += v;
    return values.empty() ? 0.0 : sum / double(values.size());
}

// A /proc/self/status field in MiB (VmRSS: resident now, VmHWM: the peak); 0 where unavailable.
double statusMegabytes(const std::string& field)
{
    std::ifstream status("/proc/self/status");
    std::string line;
    while (std::getline(status, line)) {
        if (line.starts_with(field))
            return std::stod(line.substr(field.size())) / 1024.0;
    }
    return 0.0;
}
double residentMegabytes()
{
    return statusMegabytes("VmRSS:");
}
double peakResidentMegabytes()
{
    return statusMegabytes("VmHWM:");
}

// CPU time of the whole process (every thread: capture, detection, the rasteriser's), which
// a loaded machine hardly changes, unlike the wall-clock frame time.
double processCpuMs()
{
    timespec time{};
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &time);
    return double(time.tv_sec) * 1e3 + double(time.tv_nsec) * 1e-6;
}

constexpr double kMegabyte = 1024.0 * 1024.0;

// glibc's heap at the end of the run, in MiB: bytes in use, free bytes its arenas keep (resident
// or not), and blocks mapped on their own (issue 18: where the resident memory goes).
Json heapFigures()
{
#if defined(__SANITIZE_ADDRESS__)
    // Under AddressSanitizer its allocator serves the heap and mallinfo2 reads zeros: its own
    // counters instead (free: what it keeps mapped beyond what is allocated).
    const double inUse = double(__sanitizer_get_current_allocated_bytes());
    const double heap = double(__sanitizer_get_heap_size());
    return Json{{"in_use_mb", jsonDecimals(inUse / kMegabyte, 1)},
                {"free_mb", jsonDecimals(std::max(0.0, heap - inUse) / kMegabyte, 1)},
                {"mapped_mb", jsonDecimals(0.0, 1)}};
#else
    const struct mallinfo2 info = mallinfo2();
    return Json{{"in_use_mb", jsonDecimals(double(info.uordblks + info.hblkhd) / kMegabyte, 1)},
                {"free_mb", jsonDecimals(double(info.fordblks) / kMegabyte, 1)},
                {"mapped_mb", jsonDecimals(double(info.hblkhd) / kMegabyte, 1)}};
#endif
}

} // namespace

int benchCommand(const BenchCommandOptions& options)
{
    const long frames = options.frames;
    const long warmup = options.warmup;

    Config config = configFromOptions(options.config);
    if (!options.environmentSource.empty()) {
        config.environment.source = options.environmentSource;
        if (config.environment.source == "camera+hdr" && config.environment.hdr.empty())
            throw InputError("--environment-source camera+hdr: the configuration names no [environment] hdr");
    }
    const bool profile = !options.noProfile;
    Pipeline pipeline(config, profile, nullptr, options.replay ? int(options.replayFrames) : 0);
    const auto* replay = dynamic_cast<const ReplaySource*>(&pipeline.captureSource());
    // As the daemon runs: detection on its own thread, never waited for.
    if (!options.syncDetection)
        pipeline.detectInBackground();
    FrameReport report;
    for (long i = 0; i < warmup; ++i)
        if (!pipeline.step(report))
            throw InputError("the camera source ended during warm-up");

    std::vector<double> frameMs, captureMs, detectMs, renderMs, readbackMs, latencyMs;
    // Each render stage's wall and CPU milliseconds per frame (RenderStats).
    using StageField = StageTime RenderStats::*;
    const std::pair<const char*, StageField> stageFields[] = {{"env_maps", &RenderStats::environmentMaps},
                                                              {"sh", &RenderStats::sh},
                                                              {"prefilter", &RenderStats::prefilter},
                                                              {"shading", &RenderStats::shading},
                                                              {"transparent", &RenderStats::transparent},
                                                              {"shadows", &RenderStats::shadows},
                                                              {"receivers", &RenderStats::receivers},
                                                              {"background", &RenderStats::background},
                                                              {"environment_capture", &RenderStats::environmentCapture},
                                                              {"post", &RenderStats::post},
                                                              {"animation", &RenderStats::animation}};
    std::vector<std::vector<double>> stageWallMs(std::size(stageFields)), stageCpuMs(std::size(stageFields));
    std::vector<double> mapsUpdated, shProjected, mapsPrefiltered, shadowMapDrawn;
    for (auto* v : {&frameMs, &captureMs, &detectMs, &renderMs, &readbackMs, &latencyMs, &mapsUpdated, &shProjected,
                    &mapsPrefiltered, &shadowMapDrawn})
        v->reserve(size_t(frames));
    long measured = 0;
    const double cpuStart = processCpuMs();
    const auto start = std::chrono::steady_clock::now();
    auto last = start;
    while (measured < frames && pipeline.step(report)) {
        const auto now = std::chrono::steady_clock::now();
        frameMs.push_back(std::chrono::duration<double, std::milli>(now - last).count());
        last = now;
        captureMs.push_back(report.times.captureMs);
        detectMs.push_back(report.times.detectMs);
        renderMs.push_back(report.times.renderMs);
        readbackMs.push_back(report.times.readbackMs);
        if (report.latencyMs)
            latencyMs.push_back(*report.latencyMs);
        const RenderStats stats = pipeline.renderStats();
        for (size_t s = 0; s < std::size(stageFields); ++s) {
            stageWallMs[s].push_back((stats.*stageFields[s].second).wallMs);
            stageCpuMs[s].push_back((stats.*stageFields[s].second).cpuMs);
        }
        mapsUpdated.push_back(stats.mapsUpdated);
        shProjected.push_back(stats.shProjected);
        mapsPrefiltered.push_back(stats.mapsPrefiltered);
        shadowMapDrawn.push_back(stats.shadowMapDrawn);
        ++measured;
    }
    const double seconds = std::chrono::duration<double>(last - start).count();
    const double fps = seconds > 0 ? double(measured) / seconds : 0.0;
    const double cpuPerFrame = measured > 0 ? (processCpuMs() - cpuStart) / double(measured) : 0.0;
    const int width = pipeline.output().width, height = pipeline.output().height;
    // The camera the figures are for: live (drawn or decoded while timed) or replayed from memory.
    const std::string source = replay ? "replay" : "live";
    const double replayMegabytes = replay ? double(replay->bytesHeld()) / kMegabyte : 0.0;
    // Read once each, the peak after the current figure (so the peak is never below it): the
    // peak and the peak less the replayed frames are then of the same moment.
    const double residentMb = residentMegabytes();
    const double peakMegabytes = peakResidentMegabytes();
    // The resident figure split: the process's own memory (heap, GL objects, the frames) and
    // the pages of mapped files (libraries' code and constants: the ones not run since
    // start-up are dropped from the resident set once it is over, pipeline.cpp).
    const double residentAnonMb = statusMegabytes("RssAnon:");
    const double residentFileMb = statusMegabytes("RssFile:") + statusMegabytes("RssShmem:");
    const double latencyP50 = percentile(latencyMs, 0.5), latencyP99 = percentile(latencyMs, 0.99);

    if (options.json) {
        Json stages = {{"capture", jsonDecimals(mean(captureMs), 3)},
                       {"detect", jsonDecimals(mean(detectMs), 3)},
                       {"render", jsonDecimals(mean(renderMs), 3)},
                       {"readback", jsonDecimals(mean(readbackMs), 3)}};
        Json stagesCpu = Json::object();
        if (profile) {
            for (size_t s = 0; s < std::size(stageFields); ++s) {
                stages[stageFields[s].first] = jsonDecimals(mean(stageWallMs[s]), 3);
                stagesCpu[stageFields[s].first] = jsonDecimals(mean(stageCpuMs[s]), 3);
            }
        }
        const Json summary = {
            {"source", source},
            {"camera", config.camera.source},
            {"replay",
             replay ? Json{{"frames", replay->framesHeld()}, {"mb", jsonDecimals(replayMegabytes, 1)}} : Json(nullptr)},
            {"frames", measured},
            {"width", width},
            {"height", height},
            {"fps", jsonDecimals(fps, 2)},
            {"frame_ms",
             {{"p50", jsonDecimals(percentile(frameMs, 0.5), 3)}, {"p99", jsonDecimals(percentile(frameMs, 0.99), 3)}}},
            {"latency_ms", latencyMs.empty()
                               ? Json(nullptr)
                               : Json{{"p50", jsonDecimals(latencyP50, 3)}, {"p99", jsonDecimals(latencyP99, 3)}}},
            {"frames_dropped", pipeline.framesDropped()},
            {"stages_ms", std::move(stages)},
            {"stages_cpu_ms", profile ? std::move(stagesCpu) : Json(nullptr)},
            {"cpu_ms_per_frame", jsonDecimals(cpuPerFrame, 2)},
            {"env_maps_per_frame", jsonDecimals(mean(mapsUpdated), 2)},
            // Of those, the sets whose diffuse (SH) and glossy maps were rebuilt: only where
            // the object's materials read them (a chrome object reads its mirror map alone).
            {"env_maps_sh_per_frame", jsonDecimals(mean(shProjected), 2)},
            {"env_maps_prefiltered_per_frame", jsonDecimals(mean(mapsPrefiltered), 2)},
            // The share of the shadow map drawn per frame (0: kept from the frame before).
            {"shadow_map_drawn_per_frame", jsonDecimals(mean(shadowMapDrawn), 3)},
            {"profiled", profile},
            {"rss_mb", jsonDecimals(residentMb, 1)},
            {"rss_anon_mb", jsonDecimals(residentAnonMb, 1)},
            {"rss_file_mb", jsonDecimals(residentFileMb, 1)},
            {"peak_rss_mb", jsonDecimals(peakMegabytes, 1)},
            // What a device with a real camera would hold: the replayed frames are the bench's
            // stand-in for the camera (held from before the first frame to the end, so the
            // peak holds all of them); a camera's own buffers are the driver's.
            {"peak_rss_less_replay_mb", jsonDecimals(peakMegabytes - replayMegabytes, 1)},
            {"heap", heapFigures()}};
        std::printf("%s\n", jsonLine(summary).c_str());
    } else {
        std::printf("%ld frames at %dx%d, %s camera: %.1f fps, frame time p50 %.2f ms, p99 %.2f ms\n", measured, width,
                    height, source.c_str(), fps, percentile(frameMs, 0.5), percentile(frameMs, 0.99));
        if (replay)
            std::printf("  replay: %d frames held, %.1f MiB\n", replay->framesHeld(), replayMegabytes);
        if (!latencyMs.empty())
            std::printf("  capture to present: p50 %.2f ms, p99 %.2f ms\n", latencyP50, latencyP99);
        std::printf("  resident %.0f MiB (%.0f MiB own, %.0f MiB of mapped files), peak %.0f MiB", residentMb,
                    residentAnonMb, residentFileMb, peakMegabytes);
        if (replay)
            std::printf(" (%.0f MiB less the replayed frames)", peakMegabytes - replayMegabytes);
        std::printf("\n");
        std::printf("  %-9s %8s %8s %8s\n", "stage", "mean", "p50", "p99");
        const std::pair<const char*, const std::vector<double>*> stages[] = {
            {"capture", &captureMs}, {"detect", &detectMs}, {"render", &renderMs}, {"readback", &readbackMs}};
        for (const auto& [name, values] : stages)
            std::printf("  %-9s %8.2f %8.2f %8.2f\n", name, mean(*values), percentile(*values, 0.5),
                        percentile(*values, 0.99));
        const unsigned cores = std::max(1U, std::thread::hardware_concurrency());
        std::printf("  CPU time %.1f ms per frame, all threads (at most %.1f fps on %u cores)\n", cpuPerFrame,
                    cpuPerFrame > 0 ? 1000.0 * cores / cpuPerFrame : 0.0, cores);
        if (profile) {
            std::printf("  render, split (%.2f environment maps updated per frame, %.2f with SH, %.2f prefiltered; "
                        "cpu: rendering threads):\n",
                        mean(mapsUpdated), mean(shProjected), mean(mapsPrefiltered));
            std::printf("    %-19s %6s %8s %8s %8s\n", "stage", "mean", "p50", "p99", "cpu");
            for (size_t s = 0; s < std::size(stageFields); ++s)
                std::printf("    %-19s %6.2f %8.2f %8.2f %8.2f\n", stageFields[s].first, mean(stageWallMs[s]),
                            percentile(stageWallMs[s], 0.5), percentile(stageWallMs[s], 0.99), mean(stageCpuMs[s]));
        }
    }
    return kExitOk;
}

} // namespace lumar
