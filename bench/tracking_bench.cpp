#include "bench/tracking_bench.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <memory>

#include <opencv2/core.hpp>
#ifdef LUMAR_HAVE_ARUCO
#include <opencv2/aruco.hpp>
#endif

#include "bench/tracking_bench_scene.h"
#include "bench/tracking_scoring.h"
#include "core/error.h"
#include "core/json_output.h"
#include "tracking/tag_tracker.h"

namespace lumar {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr int kMaxFramesPerCondition = 10000;

TagSizes sizesOf(const BenchCondition& condition)
{
    TagSizes sizes;
    for (const BenchTag& tag : condition.tags)
        sizes.byId[tag.id] = tag.size;
    return sizes;
}

// The detectors compared. restart() begins a condition: a new sequence, no history.
class Detector {
public:
    virtual ~Detector() = default;
    [[nodiscard]] virtual const char* name() const = 0;
    virtual void restart(const BenchCondition& condition) = 0;
    virtual std::vector<TagDetection> detect(const Image8& luma) = 0;
};

class LumarDetector final : public Detector {
public:
    explicit LumarDetector(const CameraIntrinsics& k) : k_(k) {}
    [[nodiscard]] const char* name() const override { return "lumar"; }
    void restart(const BenchCondition& condition) override
    {
        TrackingConfig config; // the [tracking] defaults of lumar.toml
        config.threads = 1;    // as the AprilTag defaults (and the library's limit on Debian 12)
        tracker_ = std::make_unique<TagTracker>(config, k_, sizesOf(condition));
    }
    std::vector<TagDetection> detect(const Image8& luma) override { return tracker_->detect(luma); }

private:
    CameraIntrinsics k_;
    std::unique_ptr<TagTracker> tracker_;
};

class AprilTagDefaultsDetector final : public Detector {
public:
    explicit AprilTagDefaultsDetector(const CameraIntrinsics& k) : k_(k) {}
    [[nodiscard]] const char* name() const override { return "apriltag"; }
    void restart(const BenchCondition& condition) override { sizes_ = sizesOf(condition); }
    std::vector<TagDetection> detect(const Image8& luma) override { return library_.detect(luma, sizes_, k_); }
    [[nodiscard]] std::string settings() const { return library_.settings(); }

private:
    CameraIntrinsics k_;
    AprilTagDefaults library_;
    TagSizes sizes_;
};

#ifdef LUMAR_HAVE_ARUCO
class ArucoDetector final : public Detector {
public:
    explicit ArucoDetector(const CameraIntrinsics& k)
        : k_(k), dictionary_(cv::aruco::getPredefinedDictionary(cv::aruco::DICT_APRILTAG_36h11)),
          parameters_(cv::aruco::DetectorParameters::create())
    {
    }
    [[nodiscard]] const char* name() const override { return "opencv_aruco"; }
    void restart(const BenchCondition& condition) override { sizes_ = sizesOf(condition); }
    std::vector<TagDetection> detect(const Image8& luma) override
    {
        const cv::Mat image(luma.height, luma.width, CV_8UC1, const_cast<uint8_t*>(luma.data.data()));
        std::vector<std::vector<cv::Point2f>> corners;
        std::vector<int> ids;
        cv::aruco::detectMarkers(image, dictionary_, corners, ids, parameters_);
        std::vector<TagDetection> result;
        for (size_t i = 0; i < ids.size(); ++i) {
            TagDetection f;
            f.id = ids[i];
            // Both orders run the same way round the image; OpenCV's DICT_APRILTAG_36h11 codes
            // are the library's turned by 180 degrees, so ArUco's first corner is AprilTag's third.
            constexpr std::array<size_t, 4> kFromAruco{1, 0, 3, 2};
            for (size_t c = 0; c < 4; ++c)
                f.corners[c] = {corners[i][kFromAruco[c]].x, corners[i][kFromAruco[c]].y};
            const double size = sizes_.of(f.id);
            f.hasPose = size > 0.0 && solveTagPose(f.corners, size, k_, f.cameraFromMarker, f.reprojectionErrorPx);
            result.push_back(f);
        }
        return result;
    }

private:
    CameraIntrinsics k_;
    cv::Ptr<cv::aruco::Dictionary> dictionary_;
    cv::Ptr<cv::aruco::DetectorParameters> parameters_;
    TagSizes sizes_;
};
#endif

struct Tally {
    int frames = 0, visible = 0, found = 0, falsePositives = 0;
    double ms = 0.0;
    std::vector<double> corner, rotation, translation;

    void add(const Tally& o)
    {
        frames += o.frames;
        visible += o.visible;
        found += o.found;
        falsePositives += o.falsePositives;
        ms += o.ms;
        corner.insert(corner.end(), o.corner.begin(), o.corner.end());
        rotation.insert(rotation.end(), o.rotation.begin(), o.rotation.end());
        translation.insert(translation.end(), o.translation.begin(), o.translation.end());
    }
};

void score(const std::vector<BenchTagTruth>& truths, const std::vector<TagDetection>& found, Tally& t)
{
    ++t.frames;
    const FrameMatch match = matchDetections(truths, found);
    t.falsePositives += match.falsePositives;
    for (size_t i = 0; i < truths.size(); ++i) {
        const BenchTagTruth& truth = truths[i];
        // A tag cut by the image's edge found: right, but not counted in recall.
        if (!truth.visible)
            continue;
        ++t.visible;
        if (match.detectionOf[i] < 0)
            continue;
        const TagDetection& f = found[size_t(match.detectionOf[i])];
        ++t.found;
        for (size_t c = 0; c < 4; ++c)
            t.corner.push_back(glm::length(f.corners[c] - truth.corners[c]));
        if (f.hasPose) {
            t.rotation.push_back(rotationErrorDeg(f.cameraFromMarker.R, truth.cameraFromMarker.R));
            t.translation.push_back(100.0 * glm::length(f.cameraFromMarker.t - truth.cameraFromMarker.t) /
                                    glm::length(truth.cameraFromMarker.t));
        }
    }
}

TrackingBenchRow makeRow(const std::string& condition, const std::string& detector, const Tally& t)
{
    TrackingBenchRow r;
    r.condition = condition;
    r.detector = detector;
    r.frames = t.frames;
    r.visibleTags = t.visible;
    r.found = t.found;
    r.falsePositives = t.falsePositives;
    r.recall = t.visible > 0 ? double(t.found) / t.visible : kNaN;
    r.falsePositivesPerFrame = t.frames > 0 ? double(t.falsePositives) / t.frames : kNaN;
    r.cornerMeanPx = mean(t.corner);
    r.cornerP95Px = percentile95(t.corner);
    r.rotationMeanDeg = mean(t.rotation);
    r.rotationP95Deg = percentile95(t.rotation);
    r.translationMeanPercent = mean(t.translation);
    r.translationP95Percent = percentile95(t.translation);
    r.msPerFrame = t.frames > 0 ? t.ms / t.frames : kNaN;
    return r;
}

} // namespace

TrackingBenchReport runTrackingBench(const TrackingBenchOptions& options)
{
    if (options.framesPerCondition < 1 || options.framesPerCondition > kMaxFramesPerCondition)
        throw InputError("tracking bench: frames per condition must be in [1, 10000], got " +
                         std::to_string(options.framesPerCondition));
    const TrackingBenchScene scene(options.width, options.height, options.seed);
    const CameraIntrinsics& k = scene.intrinsics();

    auto aprilTag = std::make_unique<AprilTagDefaultsDetector>(k);
    TrackingBenchReport report;
    report.options = options;
    report.notes.push_back(std::to_string(options.width) + "x" + std::to_string(options.height) + ", fx " +
                           fixed(k.fx, 1) + " px (70 deg horizontal field of view), " +
                           std::to_string(options.framesPerCondition) + " frames per condition, seed " +
                           std::to_string(options.seed) + "; tags rendered at 4x4 samples per pixel.");
    report.notes.push_back("apriltag: libapriltag " LUMAR_APRILTAG_VERSION
                           " with apriltag_detector_create()'s defaults (" +
                           aprilTag->settings() +
                           "); its corners are shifted by -0.5 px into OpenCV's pixel convention, as lumar's tracker "
                           "does; pose from lumar's IPPE solver (solveTagPose) without history.");
    report.notes.push_back("lumar: TagTracker with lumar.toml's [tracking] defaults (quad_decimate 2, ROI search "
                           "around the last detections, a full-frame search at least every 10 frames, restarted per "
                           "condition), 1 thread (libapriltag before 3.4.3 crashes with nthreads > 1); its own pose "
                           "(IPPE, ambiguity resolved with the previous pose).");

    std::vector<std::unique_ptr<Detector>> detectors;
    detectors.push_back(std::make_unique<LumarDetector>(k));
    detectors.push_back(std::move(aprilTag));
#ifdef LUMAR_HAVE_ARUCO
    detectors.push_back(std::make_unique<ArucoDetector>(k));
    report.notes.push_back(
        "opencv_aruco: OpenCV " CV_VERSION " contrib aruco, DICT_APRILTAG_36h11, "
        "DetectorParameters defaults (no corner refinement), 1 thread (cv::setNumThreads(1)), corners as "
        "returned (already in OpenCV's pixel convention); pose "
        "from lumar's IPPE solver without history.");
#else
    report.notes.push_back("opencv_aruco: skipped, this build has no OpenCV aruco module (Debian: "
                           "libopencv-contrib-dev).");
#endif
    for (const auto& d : detectors)
        report.detectors.emplace_back(d->name());

    // OpenCV's thread pool would give ArUco (and nothing else) several cores: detectors run
    // with one, the rendering with all.
    const int openCvThreads = cv::getNumThreads();
    const auto& conditions = TrackingBenchScene::conditions();
    std::vector<Tally> overall(detectors.size());
    BenchFrame frame;
    try {
        for (size_t c = 0; c < conditions.size(); ++c) {
            report.conditions.push_back(conditions[c].name);
            std::vector<Tally> tallies(detectors.size());
            for (auto& d : detectors)
                d->restart(conditions[c]);
            for (int f = 0; f < options.framesPerCondition; ++f) {
                scene.render(c, f, options.framesPerCondition, frame);
                cv::setNumThreads(1);
                for (size_t d = 0; d < detectors.size(); ++d) {
                    const auto start = std::chrono::steady_clock::now();
                    const std::vector<TagDetection> found = detectors[d]->detect(frame.luma);
                    tallies[d].ms +=
                        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
                    score(frame.tags, found, tallies[d]);
                }
                cv::setNumThreads(openCvThreads);
            }
            for (size_t d = 0; d < detectors.size(); ++d) {
                report.rows.push_back(makeRow(conditions[c].name, detectors[d]->name(), tallies[d]));
                overall[d].add(tallies[d]);
            }
        }
    } catch (...) {
        cv::setNumThreads(openCvThreads);
        throw;
    }
    for (size_t d = 0; d < detectors.size(); ++d)
        report.rows.push_back(makeRow("overall", detectors[d]->name(), overall[d]));
    const double lumarMs = overall[0].ms, aprilTagMs = overall[1].ms;
    report.lumarOverAprilTagTime = aprilTagMs > 0.0 ? lumarMs / aprilTagMs : kNaN;
    return report;
}

std::string trackingBenchMarkdown(const TrackingBenchReport& report)
{
    MarkdownTable table({"condition", "detector", "frames", "tags", "recall", "FP/frame", "corner mean px",
                         "corner p95 px", "rot mean deg", "rot p95 deg", "trans mean %", "trans p95 %", "ms/frame"},
                        2);
    for (const TrackingBenchRow& r : report.rows)
        table.add({r.condition, r.detector, std::to_string(r.frames), std::to_string(r.visibleTags), fixed(r.recall, 3),
                   fixed(r.falsePositivesPerFrame, 3), fixed(r.cornerMeanPx, 3), fixed(r.cornerP95Px, 3),
                   fixed(r.rotationMeanDeg, 2), fixed(r.rotationP95Deg, 2), fixed(r.translationMeanPercent, 2),
                   fixed(r.translationP95Percent, 2), fixed(r.msPerFrame, 2)});
    std::string out = table.str();
    out += "\nTime per frame, lumar / apriltag defaults (overall): " + fixed(report.lumarOverAprilTagTime, 3) +
           " (target <= 0.5 with recall and corner error no worse)\n\n";
    for (const std::string& note : report.notes)
        out += "- " + note + "\n";
    return out;
}

std::string trackingBenchJson(const TrackingBenchReport& report)
{
    // Json keeps the keys in the order written here, the order of the table's columns.
    Json rows = Json::array();
    for (const TrackingBenchRow& r : report.rows)
        rows.push_back({{"condition", r.condition},
                        {"detector", r.detector},
                        {"frames", r.frames},
                        {"visible_tags", r.visibleTags},
                        {"found", r.found},
                        {"false_positives", r.falsePositives},
                        {"recall", jsonNumber(r.recall)},
                        {"false_positives_per_frame", jsonNumber(r.falsePositivesPerFrame)},
                        {"corner_mean_px", jsonNumber(r.cornerMeanPx)},
                        {"corner_p95_px", jsonNumber(r.cornerP95Px)},
                        {"rotation_mean_deg", jsonNumber(r.rotationMeanDeg)},
                        {"rotation_p95_deg", jsonNumber(r.rotationP95Deg)},
                        {"translation_mean_percent", jsonNumber(r.translationMeanPercent)},
                        {"translation_p95_percent", jsonNumber(r.translationP95Percent)},
                        {"ms_per_frame", jsonNumber(r.msPerFrame)}});
    const Json j = {{"width", report.options.width},
                    {"height", report.options.height},
                    {"frames_per_condition", report.options.framesPerCondition},
                    {"seed", report.options.seed},
                    {"conditions", report.conditions},
                    {"detectors", report.detectors},
                    {"rows", std::move(rows)},
                    {"lumar_over_apriltag_time", jsonNumber(report.lumarOverAprilTagTime)},
                    {"notes", report.notes}};
    return jsonLine(j) + "\n";
}

} // namespace lumar
