#include "bench/tracking_overhead.h"

#include <algorithm>
#include <chrono>
#include <fstream>
#include <functional>
#include <memory>
#include <vector>

#include <apriltag/apriltag.h>

#include "bench/tracking_bench_scene.h"
#include "bench/tracking_scoring.h"
#include "core/error.h"
#include "tracking/apriltag_family.h"
#include "tracking/tag_tracker.h"

namespace lumar {
namespace {

using Clock = std::chrono::steady_clock;

double msSince(Clock::time_point start)
{
    return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}

std::string loadAverage()
{
    std::ifstream in("/proc/loadavg");
    std::string one, five, fifteen;
    in >> one >> five >> fifteen;
    return one + " " + five + " " + fifteen;
}

struct DetectorDeleter {
    void operator()(apriltag_detector_t* d) const { apriltag_detector_destroy(d); }
};

// The library configured as lumar's tracker configures it, with lumar's pose per detection.
class LibraryCall {
public:
    LibraryCall(const TrackingConfig& config, const CameraIntrinsics& k, TagSizes sizes)
        : family_(createAprilTagFamily(config.family)), detector_(apriltag_detector_create()), k_(k),
          sizes_(std::move(sizes))
    {
        if (!detector_)
            throw RuntimeError("cannot create the AprilTag detector");
        detector_->quad_decimate = float(config.quadDecimate);
        detector_->quad_sigma = float(config.quadSigma);
        detector_->refine_edges = config.refineEdges;
        detector_->decode_sharpening = config.decodeSharpening;
        detector_->nthreads = 1;
        apriltag_detector_add_family_bits(detector_.get(), family_.get(), correctableBitsFor(*family_));
    }
    // Returns the number of detections; adds the pose's share of the time to `poseMs`.
    int detect(const Image8& luma, double& poseMs)
    {
        image_u8_t image{luma.width, luma.height, luma.width, const_cast<uint8_t*>(luma.data.data())};
        zarray_t* detections = apriltag_detector_detect(detector_.get(), &image);
        if (!detections)
            throw RuntimeError("AprilTag detection failed");
        const auto start = Clock::now();
        const int count = zarray_size(detections);
        for (int i = 0; i < count; ++i) {
            apriltag_detection_t* det = nullptr;
            zarray_get(detections, i, &det);
            std::array<glm::dvec2, 4> corners;
            for (size_t c = 0; c < 4; ++c)
                corners[c] = {det->p[c][0] - 0.5, det->p[c][1] - 0.5};
            const double size = sizes_.of(det->id);
            TagPoseSolution solution;
            if (size > 0.0)
                solveTagPose(corners, size, k_, solution);
        }
        poseMs += msSince(start);
        apriltag_detections_destroy(detections);
        return count;
    }

private:
    AprilTagFamilyPtr family_; // outlives the detector, which borrows it
    std::unique_ptr<apriltag_detector_t, DetectorDeleter> detector_;
    CameraIntrinsics k_;
    TagSizes sizes_;
};

} // namespace

std::string runTrackingOverhead(const TrackingOverheadOptions& options)
{
    if (options.frames < 1 || options.frames > 1000 || options.rounds < 1 || options.rounds > 100)
        throw InputError("tracking overhead: frames must be in [1, 1000] and rounds in [1, 100]");
    const TrackingBenchScene scene(options.width, options.height, options.seed);
    const CameraIntrinsics& k = scene.intrinsics();
    const auto& conditions = TrackingBenchScene::conditions();

    // Condition-major, consecutive frames of each: the video row follows them in order.
    std::vector<Image8> frames;
    std::vector<size_t> conditionOf;
    TagSizes sizes;
    const int perCondition = std::max(1, options.frames / int(conditions.size()));
    for (size_t c = 0; c < conditions.size() && int(frames.size()) < options.frames; ++c) {
        for (const BenchTag& tag : conditions[c].tags)
            sizes.byId.try_emplace(tag.id, tag.size);
        for (int f = 0; f < perCondition && int(frames.size()) < options.frames; ++f) {
            BenchFrame frame;
            scene.render(c, f, perCondition, frame);
            frames.push_back(std::move(frame.luma));
            conditionOf.push_back(c);
        }
    }

    TrackingConfig fullFrame; // lumar.toml's [tracking] defaults, the full frame every time
    fullFrame.threads = 1;
    fullFrame.roi = false;
    TrackingConfig video = fullFrame;
    video.roi = true;
    LibraryCall library(fullFrame, k, sizes);
    TagTracker full(fullFrame, k, sizes);
    TagTracker stills(fullFrame, k, sizes);
    TagTracker following(video, k, sizes);
    const size_t slowFrames = std::min<size_t>(frames.size(), 3);

    struct Series {
        std::string name;
        std::vector<double> msPerFrame;
    };
    Series lib{"library: apriltag_detector_detect + pose", {}}, libPose{"  of which pose", {}},
        lumarFull{"lumar full frame: TagTracker::detect, roi off", {}},
        lumarStills{"lumar detect on stills: reset + detect", {}},
        lumarNew{"former lumar detect: new TagTracker + detect", {}},
        lumarVideo{"lumar video: detect with the ROI search", {}};
    int libraryDetections = 0, lumarDetections = 0;

    const auto timeLibrary = [&] {
        double poseMs = 0.0;
        int count = 0;
        const auto start = Clock::now();
        for (const Image8& f : frames)
            count += library.detect(f, poseMs);
        lib.msPerFrame.push_back(msSince(start) / double(frames.size()));
        libPose.msPerFrame.push_back(poseMs / double(frames.size()));
        libraryDetections = count;
    };
    const auto timeFull = [&] {
        int count = 0;
        const auto start = Clock::now();
        for (const Image8& f : frames)
            count += int(full.detect(f).size());
        lumarFull.msPerFrame.push_back(msSince(start) / double(frames.size()));
        lumarDetections = count;
    };
    const auto timeStills = [&] {
        const auto start = Clock::now();
        for (const Image8& f : frames) {
            stills.reset(k);
            (void)stills.detect(f);
        }
        lumarStills.msPerFrame.push_back(msSince(start) / double(frames.size()));
    };
    const auto timeNewTracker = [&] {
        const auto start = Clock::now();
        for (size_t i = 0; i < slowFrames; ++i) {
            TagTracker fresh(fullFrame, k, sizes);
            (void)fresh.detect(frames[i]);
        }
        lumarNew.msPerFrame.push_back(msSince(start) / double(slowFrames));
    };
    const auto timeVideo = [&] {
        const auto start = Clock::now();
        for (size_t i = 0; i < frames.size(); ++i) {
            if (i == 0 || conditionOf[i] != conditionOf[i - 1])
                following.reset(k); // a new sequence
            (void)following.detect(frames[i]);
        }
        lumarVideo.msPerFrame.push_back(msSince(start) / double(frames.size()));
    };
    std::vector<std::function<void()>> runs{timeLibrary, timeFull, timeStills, timeNewTracker, timeVideo};
    const std::string loadBefore = loadAverage();
    std::vector<double> fullRatio, stillsRatio;
    for (int round = 0; round < options.rounds; ++round) {
        // Alternate the order, so that neither side always runs first (caches, clock ramps).
        if (round % 2 == 0)
            for (auto& run : runs)
                run();
        else
            for (auto it = runs.rbegin(); it != runs.rend(); ++it)
                (*it)();
        fullRatio.push_back(lumarFull.msPerFrame.back() / lib.msPerFrame.back());
        stillsRatio.push_back(lumarStills.msPerFrame.back() / lib.msPerFrame.back());
    }
    const std::string loadAfter = loadAverage();

    std::string out = "| ms per frame | rounds | median |\n|---|---|---:|\n";
    for (const Series* s : {&lib, &libPose, &lumarFull, &lumarStills, &lumarNew, &lumarVideo}) {
        std::string values;
        for (double v : s->msPerFrame)
            values += (values.empty() ? "" : " ") + fixed(v, 2);
        out += "| " + s->name + " | " + values + " | " + fixed(median(s->msPerFrame), 2) + " |\n";
    }
    out += "\nlumar full frame / library: median " + fixed(median(fullRatio), 3) + " (per round:";
    for (double r : fullRatio)
        out += " " + fixed(r, 3);
    out += ")\nlumar detect on stills / library: median " + fixed(median(stillsRatio), 3) + " (per round:";
    for (double r : stillsRatio)
        out += " " + fixed(r, 3);
    out += ")\n\n- " + std::to_string(frames.size()) + " frames of " + std::to_string(options.width) + "x" +
           std::to_string(options.height) + " (" + std::to_string(perCondition) +
           " consecutive per condition), rendered before timing; " + std::to_string(options.rounds) +
           " rounds, the order reversed every other round; the former `lumar detect` timed on " +
           std::to_string(slowFrames) + " frames per round.\n- detections per pass: library " +
           std::to_string(libraryDetections) + ", lumar full frame " + std::to_string(lumarDetections) +
           ".\n- lumar video, over all rounds: " + std::to_string(following.searchCounts().frames) + " frames, " +
           std::to_string(following.searchCounts().windowSearches) + " searched in windows, " +
           std::to_string(following.searchCounts().fullSearches) + " in full, " +
           std::to_string(following.searchCounts().fallbacks) +
           " of them after windows that missed a tag of the last frame (or cut one).\n- load average before: " +
           loadBefore + ", after: " + loadAfter + ".\n";
    return out;
}

} // namespace lumar
