#include "bench/tracking_sequences.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <functional>
#include <limits>
#include <memory>
#include <optional>

#include <apriltag/apriltag.h>
#include <glm/gtc/quaternion.hpp>

#include "bench/tracking_bench.h"
#include "bench/tracking_bench_scene.h"
#include "core/error.h"
#include "core/json_output.h"
#include "tracking/apriltag_family.h"
#include "tracking/tag_map.h"
#include "tracking/tag_tracker.h"
#include "tracking/tracked_poses.h"

namespace lumar {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kDeg = kPi / 180.0;
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kFps = 30.0;
constexpr int kMapTarget = -1; // Sequence::target: the board's map pose

// The camera at `eye` looking at `aim` on the plane z = 0, the world's -y seen upright
// (OpenCV axes: x right, y down, z forward), as the benchmark's scene aims it.
Pose lookAt(const glm::dvec3& eye, const glm::dvec3& aim)
{
    const glm::dvec3 forward = glm::normalize(aim - eye);
    const glm::dvec3 minusY(0.0, -1.0, 0.0);
    const glm::dvec3 down = glm::normalize(minusY - glm::dot(minusY, forward) * forward);
    const glm::dvec3 right = glm::cross(down, forward);
    Pose pose;
    for (int i = 0; i < 3; ++i) {
        pose.R[i][0] = right[i];
        pose.R[i][1] = down[i];
        pose.R[i][2] = forward[i];
    }
    pose.t = -(pose.R * eye);
    return pose;
}

// The camera `distance` from `aim`, tilted `tiltDeg` from the plane's normal towards -y.
Pose viewOf(const glm::dvec3& aim, double distance, double tiltDeg)
{
    const double tilt = tiltDeg * kDeg;
    return lookAt(aim + distance * glm::dvec3(0.0, -std::sin(tilt), std::cos(tilt)), aim);
}

struct Sequence {
    std::string name;
    BenchCondition scene; // tags and degradations; covered and blur set per frame
    int frames = 60;
    std::function<Pose(int)> cameraFromWorld;
    std::function<std::vector<int>(int)> covered = [](int) { return std::vector<int>{}; };
    std::function<double(int)> blurPx = [](int) { return 0.0; }; // along the x axis of the image
    std::function<bool(int)> still = [](int) { return false; };
    std::function<bool(int)> panning = [](int) { return false; };
    int target = 0;     // the tag id whose drawn pose is scored for jitter and lag, or kMapTarget
    bool board = false; // the tags form one [[maps]] board, its frame the world's
};

std::vector<Sequence> makeSequences()
{
    std::vector<Sequence> list;
    {
        // Hidden on single frames 7 apart: every phase of a 10-frame full-frame schedule.
        Sequence s;
        s.name = "blink_low_light";
        s.scene.tags = {{0, 0.12, {-0.15, 0.0}}, {7, 0.12, {0.15, 0.0}}};
        s.scene.lowLight = true;
        s.scene.exposure = 0.2;
        s.cameraFromWorld = [](int) { return viewOf({0.0, 0.0, 0.0}, 0.9, 20.0); };
        s.covered = [](int f) { return f >= 6 && f % 7 == 6 ? std::vector<int>{0} : std::vector<int>{}; };
        s.still = [](int) { return true; };
        s.target = 7;
        list.push_back(s);
    }
    {
        // Covers of 1, 3, 7, 9 and 13 frames, ending on frames 5, 12, 23, 37 and 55.
        Sequence s;
        s.name = "occlusion_ends";
        s.scene.tags = {{0, 0.12, {-0.15, 0.0}}, {7, 0.12, {0.15, 0.0}}};
        s.cameraFromWorld = [](int) { return viewOf({0.0, 0.0, 0.0}, 0.9, 20.0); };
        s.covered = [](int f) {
            const bool hidden = (f >= 4 && f < 5) || (f >= 9 && f < 12) || (f >= 16 && f < 23) || (f >= 28 && f < 37) ||
                                (f >= 42 && f < 55);
            return hidden ? std::vector<int>{0} : std::vector<int>{};
        };
        s.still = [](int) { return true; };
        s.target = 7;
        list.push_back(s);
    }
    {
        // The aim swings 0.55 m to the left and back: tag 7 leaves on the right for a while.
        Sequence s;
        s.name = "leave_reenter";
        s.scene.tags = {{0, 0.12, {-0.35, 0.0}}, {7, 0.12, {0.35, 0.0}}};
        s.frames = 70;
        s.cameraFromWorld = [frames = s.frames](int f) {
            const double x = -0.55 * (0.5 - 0.5 * std::cos(2.0 * kPi * f / frames));
            return viewOf({x, 0.0, 0.0}, 1.0, 15.0);
        };
        s.target = 0;
        list.push_back(s);
    }
    {
        // Still for 15 frames, then the aim moves 0.025 m per frame (0.75 m/s, about 29 px per
        // frame at 0.8 m) for 20 frames with a blur of half the motion, then still again.
        Sequence s;
        s.name = "fast_pan";
        s.scene.tags = {{0, 0.16, {0.0, 0.0}}};
        s.scene.motionBlurAngleDeg = 0.0;
        s.cameraFromWorld = [](int f) {
            const double x = 0.25 - 0.025 * std::clamp(f - 15, 0, 20);
            return viewOf({x, 0.0, 0.0}, 0.8, 10.0);
        };
        s.blurPx = [](int f) { return f > 15 && f <= 35 ? 14.5 : 0.0; };
        s.still = [](int f) { return f < 15 || f >= 45; }; // the filter settled again after the pan
        s.panning = [](int f) { return f > 18 && f <= 35; };
        s.target = 0;
        list.push_back(s);
    }
    {
        // 8 cm tags 12 cm apart; the camera turns 25 degrees about the board, then stays.
        Sequence s;
        s.name = "board_4";
        s.scene.tags = {
            {10, 0.08, {-0.06, 0.06}}, {11, 0.08, {0.06, 0.06}}, {12, 0.08, {-0.06, -0.06}}, {13, 0.08, {0.06, -0.06}}};
        s.board = true;
        s.cameraFromWorld = [](int f) {
            const double azimuth = (-90.0 + 25.0 * std::min(f, 40) / 40.0) * kDeg, tilt = 30.0 * kDeg;
            const glm::dvec3 eye = 0.6 * glm::dvec3(std::sin(tilt) * std::cos(azimuth),
                                                    std::sin(tilt) * std::sin(azimuth), std::cos(tilt));
            return lookAt(eye, glm::dvec3(0.0));
        };
        s.still = [](int f) { return f >= 45; };
        s.target = kMapTarget;
        list.push_back(s);
    }
    return list;
}

TagMap boardMap(const Sequence& s)
{
    MapConfig config;
    config.name = s.name;
    for (const BenchTag& tag : s.scene.tags)
        config.tags.push_back({tag.id, tag.size, glm::dvec3(tag.position, 0.0), glm::dvec3(0.0)});
    return makeTagMap(config);
}

// What a detector gives per frame: its detections and the pose it would draw the target with.
struct FrameResult {
    std::vector<TagDetection> detections;
    std::optional<Pose> drawn;
};

class SequenceDetector {
public:
    virtual ~SequenceDetector() = default;
    [[nodiscard]] virtual std::string name() const = 0;
    virtual void restart(const Sequence& s) = 0;
    virtual void detect(const Image8& luma, int frame, FrameResult& out) = 0;
};

// lumar as `lumar render` runs it: the tracker with the [tracking] defaults (but `threads`),
// the board as a [[maps]] entry, the filtered pose at the frame's time.
class LumarSequenceDetector final : public SequenceDetector {
public:
    LumarSequenceDetector(const CameraIntrinsics& k, int threads) : k_(k), threads_(threads) {}
    [[nodiscard]] std::string name() const override { return threads_ == 1 ? "lumar" : "lumar_2threads"; }
    void restart(const Sequence& s) override
    {
        TrackingConfig config;
        config.threads = threads_;
        TagSizes sizes;
        for (const BenchTag& tag : s.scene.tags)
            sizes.byId[tag.id] = tag.size;
        tracker_ = std::make_unique<TagTracker>(config, k_, sizes);
        if (s.board)
            tracker_->setMaps({boardMap(s)});
        tracked_ = TrackedPoses(config);
        target_ = s.target;
    }
    void detect(const Image8& luma, int frame, FrameResult& out) override
    {
        out.detections = tracker_->detect(luma);
        const std::vector<MapDetection> maps = tracker_->detectMaps(out.detections);
        const auto timestampNs = int64_t(std::llround(frame * 1e9 / kFps));
        tracked_.update(out.detections, maps, uint64_t(frame), timestampNs);
        const int key = target_ == kMapTarget ? TrackedPoses::mapKey(0) : target_;
        const auto used = tracked_.poseAt(key, uint64_t(frame), timestampNs);
        out.drawn = used ? std::optional<Pose>(used->cameraFromMarker) : std::nullopt;
    }

private:
    CameraIntrinsics k_;
    int threads_;
    std::unique_ptr<TagTracker> tracker_;
    TrackedPoses tracked_;
    int target_ = 0;
};

// The AprilTag library with its defaults, frame by frame, with lumar's IPPE pose of each
// detection (no history) and lumar's map solver for the board; no filter.
class AprilTagSequenceDetector final : public SequenceDetector {
public:
    explicit AprilTagSequenceDetector(const CameraIntrinsics& k)
        : k_(k), family_(createAprilTagFamily("tag36h11")), detector_(apriltag_detector_create())
    {
        if (!detector_)
            throw RuntimeError("cannot create the AprilTag detector");
        apriltag_detector_add_family(detector_.get(), family_.get());
    }
    [[nodiscard]] std::string name() const override { return "apriltag"; }
    void restart(const Sequence& s) override
    {
        sizes_ = {};
        for (const BenchTag& tag : s.scene.tags)
            sizes_.byId[tag.id] = tag.size;
        map_ = s.board ? std::optional<TagMap>(boardMap(s)) : std::nullopt;
        target_ = s.target;
    }
    void detect(const Image8& luma, int, FrameResult& out) override
    {
        image_u8_t image{luma.width, luma.height, luma.width, const_cast<uint8_t*>(luma.data.data())};
        zarray_t* detections = apriltag_detector_detect(detector_.get(), &image);
        if (!detections)
            throw RuntimeError("AprilTag detection failed");
        out.detections.clear();
        for (int i = 0; i < zarray_size(detections); ++i) {
            apriltag_detection_t* det = nullptr;
            zarray_get(detections, i, &det);
            TagDetection d;
            d.id = det->id;
            for (size_t c = 0; c < 4; ++c)
                d.corners[c] = {det->p[c][0] - 0.5, det->p[c][1] - 0.5}; // OpenCV's pixel convention
            const double size = sizes_.of(d.id);
            d.hasPose = size > 0.0 && solveTagPose(d.corners, size, k_, d.cameraFromMarker, d.reprojectionErrorPx);
            out.detections.push_back(d);
        }
        apriltag_detections_destroy(detections);
        out.drawn.reset();
        if (map_) {
            MapDetection map;
            if (solveMapPose(*map_, out.detections, k_, map))
                out.drawn = map.cameraFromMap;
        } else {
            for (const TagDetection& d : out.detections)
                if (d.id == target_ && d.hasPose)
                    out.drawn = d.cameraFromMarker;
        }
    }

private:
    struct DetectorDeleter {
        void operator()(apriltag_detector_t* d) const { apriltag_detector_destroy(d); }
    };
    CameraIntrinsics k_;
    AprilTagFamilyPtr family_; // outlives the detector, which borrows it
    std::unique_ptr<apriltag_detector_t, DetectorDeleter> detector_;
    TagSizes sizes_;
    std::optional<TagMap> map_;
    int target_ = 0;
};

struct RenderedSequence {
    const Sequence* sequence = nullptr;
    std::vector<BenchFrame> frames;
    std::vector<Pose> targetTruth; // the target's true camera_from_marker (or _map) per frame
};

glm::dvec2 centreOf(const std::array<glm::dvec2, 4>& corners)
{
    return 0.25 * (corners[0] + corners[1] + corners[2] + corners[3]);
}

// The rotation taking `truth` to `measured` as a rotation vector (radians).
glm::dvec3 rotationError(const glm::dmat3& truth, const glm::dmat3& measured)
{
    glm::dquat q = glm::quat_cast(glm::transpose(truth) * measured);
    if (q.w < 0.0)
        q = -q;
    const glm::dvec3 v(q.x, q.y, q.z);
    const double s = glm::length(v);
    return s < 1e-15 ? glm::dvec3(0.0) : (2.0 * std::atan2(s, q.w) / s) * v;
}

double standardDeviation(const std::vector<glm::dvec3>& samples)
{
    if (samples.size() < 2)
        return kNaN;
    glm::dvec3 mean(0.0);
    for (const glm::dvec3& s : samples)
        mean += s;
    mean /= double(samples.size());
    double sum = 0.0;
    for (const glm::dvec3& s : samples)
        sum += glm::dot(s - mean, s - mean);
    return std::sqrt(sum / double(samples.size() - 1));
}

// Runs `detector` over `r` and scores it (ms per frame: this run's mean).
TrackingSequenceRow score(SequenceDetector& detector, const RenderedSequence& r)
{
    const Sequence& s = *r.sequence;
    TrackingSequenceRow row;
    row.sequence = s.name;
    row.detector = detector.name();
    row.frames = int(r.frames.size());
    detector.restart(s);
    struct TagState {
        bool wasVisible = true; // a tag visible from the first frame is no re-acquisition
        bool pending = false;
        int since = 0;
    };
    std::vector<TagState> states(s.scene.tags.size());
    std::vector<int> delays;
    std::vector<glm::dvec3> stillT, stillR;
    double lagSum = 0.0, lagMsSum = 0.0;
    int lagCount = 0;
    double seconds = 0.0;
    FrameResult result;
    for (int f = 0; f < row.frames; ++f) {
        const BenchFrame& frame = r.frames[size_t(f)];
        const auto start = std::chrono::steady_clock::now();
        detector.detect(frame.luma, f, result);
        seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        for (size_t t = 0; t < frame.tags.size(); ++t) {
            const BenchTagTruth& truth = frame.tags[t];
            TagState& state = states[t];
            bool found = false;
            for (const TagDetection& d : result.detections)
                found = found || (d.id == truth.id &&
                                  glm::length(centreOf(d.corners) - centreOf(truth.corners)) <= kMatchRadiusPx);
            if (truth.visible) {
                ++row.visibleTags;
                row.found += found ? 1 : 0;
                if (!state.wasVisible) {
                    state.pending = true;
                    state.since = 0;
                    ++row.reacquisitions;
                }
                if (state.pending) {
                    if (found) {
                        delays.push_back(state.since);
                        state.pending = false;
                    } else {
                        ++state.since;
                    }
                }
            } else if (state.pending) {
                delays.push_back(state.since); // hidden again before it was found
                state.pending = false;
            }
            state.wasVisible = truth.visible;
        }
        if (result.drawn) {
            const Pose& truth = r.targetTruth[size_t(f)];
            if (s.still(f)) {
                stillT.push_back(result.drawn->t - truth.t);
                stillR.push_back(rotationError(truth.R, result.drawn->R));
            }
            if (s.panning(f) && f > 0) {
                const glm::dvec3 velocity = truth.t - r.targetTruth[size_t(f - 1)].t; // metres per frame
                const double speed = glm::length(velocity);
                if (speed > 0.0) {
                    const double behind = glm::dot(truth.t - result.drawn->t, velocity / speed);
                    lagSum += behind;
                    lagMsSum += 1000.0 * behind / (speed * kFps);
                    ++lagCount;
                }
            }
        }
    }
    for (const TagState& state : states)
        if (state.pending)
            delays.push_back(state.since);
    row.recall = row.visibleTags > 0 ? double(row.found) / row.visibleTags : kNaN;
    row.reacquireMeanFrames = kNaN;
    if (!delays.empty()) {
        double sum = 0.0;
        for (const int d : delays)
            sum += d;
        row.reacquireMeanFrames = sum / double(delays.size());
        row.reacquireMaxFrames = *std::max_element(delays.begin(), delays.end());
    }
    row.jitterMm = 1000.0 * standardDeviation(stillT);
    row.jitterDeg = standardDeviation(stillR) / kDeg;
    row.lagMm = lagCount > 0 ? 1000.0 * lagSum / lagCount : kNaN;
    row.lagMs = lagCount > 0 ? lagMsSum / lagCount : kNaN;
    row.msPerFrame = 1000.0 * seconds / std::max(1, row.frames);
    return row;
}

double median(std::vector<double> v)
{
    std::sort(v.begin(), v.end());
    const size_t n = v.size();
    return n == 0 ? kNaN : n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

} // namespace

TrackingSequencesReport runTrackingSequences(const TrackingSequencesOptions& options)
{
    if (options.rounds < 1 || options.rounds > 100)
        throw InputError("tracking sequences: rounds must be in [1, 100], got " + std::to_string(options.rounds));
    const TrackingBenchScene scene(options.width, options.height, options.seed);
    const CameraIntrinsics& k = scene.intrinsics();
    static const std::vector<Sequence> sequences = makeSequences();

    // Every frame rendered once, before any timing.
    std::vector<RenderedSequence> rendered(sequences.size());
    for (size_t i = 0; i < sequences.size(); ++i) {
        const Sequence& s = sequences[i];
        RenderedSequence& r = rendered[i];
        r.sequence = &s;
        r.frames.resize(size_t(s.frames));
        for (int f = 0; f < s.frames; ++f) {
            BenchCondition c = s.scene;
            c.covered = s.covered(f);
            c.motionBlurPx = s.blurPx(f);
            const Pose cameraFromWorld = s.cameraFromWorld(f);
            scene.renderView(c, cameraFromWorld, options.seed * 1000003ULL + i * 1009ULL + uint64_t(f),
                             r.frames[size_t(f)]);
            if (s.target == kMapTarget) {
                r.targetTruth.push_back(cameraFromWorld); // the board's frame is the world's
            } else {
                for (const BenchTagTruth& t : r.frames[size_t(f)].tags)
                    if (t.id == s.target)
                        r.targetTruth.push_back(t.cameraFromMarker);
            }
        }
    }

    std::vector<std::unique_ptr<SequenceDetector>> detectors;
    detectors.push_back(std::make_unique<LumarSequenceDetector>(k, 1));
    detectors.push_back(std::make_unique<LumarSequenceDetector>(k, 2));
    detectors.push_back(std::make_unique<AprilTagSequenceDetector>(k));

    TrackingSequencesReport report;
    report.options = options;
    // rows[sequence][detector], scored in the first round; times of every round.
    std::vector<std::vector<TrackingSequenceRow>> rows(rendered.size(),
                                                       std::vector<TrackingSequenceRow>(detectors.size()));
    std::vector<std::vector<std::vector<double>>> times(rendered.size(),
                                                        std::vector<std::vector<double>>(detectors.size()));
    for (int round = 0; round < options.rounds; ++round)
        for (size_t i = 0; i < rendered.size(); ++i)
            for (size_t n = 0; n < detectors.size(); ++n) {
                // Odd rounds run the detectors in the reverse order: neither always goes first.
                const size_t d = round % 2 == 0 ? n : detectors.size() - 1 - n;
                TrackingSequenceRow row = score(*detectors[d], rendered[i]);
                times[i][d].push_back(row.msPerFrame);
                if (round == 0)
                    rows[i][d] = std::move(row);
            }
    for (size_t i = 0; i < rendered.size(); ++i)
        for (size_t d = 0; d < detectors.size(); ++d) {
            rows[i][d].msPerFrame = median(times[i][d]);
            report.rows.push_back(rows[i][d]);
        }
    report.notes.push_back("lumar: [tracking] defaults (roi, full frame every 10, One-Euro filter), the pose drawn "
                           "at the frame's time; lumar_2threads: the same with threads = 2 (windows on two "
                           "detectors in parallel); apriltag: the library's defaults, raw IPPE poses, the board by "
                           "lumar's map solver");
    report.notes.push_back("jitter and lag: of the target's drawn pose (board_4: the board's; others: tag 7, or tag 0 "
                           "in leave_reenter and fast_pan), against the exact pose; ms: median of " +
                           std::to_string(options.rounds) + " interleaved rounds");
    return report;
}

namespace {

std::string number(double value, int decimals)
{
    if (!std::isfinite(value))
        return "-";
    char text[32];
    std::snprintf(text, sizeof text, "%.*f", decimals, value);
    return text;
}

} // namespace

std::string trackingSequencesMarkdown(const TrackingSequencesReport& report)
{
    std::string out = "| sequence | detector | frames | visible | found | recall | re-acq. | delay mean | delay max | "
                      "jitter mm | jitter deg | lag mm | lag ms | ms/frame |\n"
                      "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n";
    for (const TrackingSequenceRow& r : report.rows) {
        out += "| " + r.sequence + " | " + r.detector + " | " + std::to_string(r.frames) + " | " +
               std::to_string(r.visibleTags) + " | " + std::to_string(r.found) + " | " + number(r.recall, 3) + " | " +
               std::to_string(r.reacquisitions) + " | " + number(r.reacquireMeanFrames, 2) + " | " +
               (r.reacquisitions > 0 ? std::to_string(r.reacquireMaxFrames) : "-") + " | " + number(r.jitterMm, 2) +
               " | " + number(r.jitterDeg, 3) + " | " + number(r.lagMm, 1) + " | " + number(r.lagMs, 1) + " | " +
               number(r.msPerFrame, 2) + " |\n";
    }
    out += "\n";
    for (const std::string& note : report.notes)
        out += "- " + note + "\n";
    return out;
}

std::string trackingSequencesJson(const TrackingSequencesReport& report)
{
    Json rows = Json::array();
    for (const TrackingSequenceRow& r : report.rows)
        rows.push_back({{"sequence", r.sequence},
                        {"detector", r.detector},
                        {"frames", r.frames},
                        {"visible", r.visibleTags},
                        {"found", r.found},
                        {"recall", jsonSignificant(r.recall, 6)},
                        {"reacquisitions", r.reacquisitions},
                        {"reacquire_mean_frames", jsonSignificant(r.reacquireMeanFrames, 6)},
                        {"reacquire_max_frames", r.reacquireMaxFrames},
                        {"jitter_mm", jsonSignificant(r.jitterMm, 6)},
                        {"jitter_deg", jsonSignificant(r.jitterDeg, 6)},
                        {"lag_mm", jsonSignificant(r.lagMm, 6)},
                        {"lag_ms", jsonSignificant(r.lagMs, 6)},
                        {"ms_per_frame", jsonSignificant(r.msPerFrame, 6)}});
    const Json j = {{"width", report.options.width},   {"height", report.options.height}, {"seed", report.options.seed},
                    {"rounds", report.options.rounds}, {"rows", std::move(rows)},         {"notes", report.notes}};
    return jsonLine(j) + "\n";
}

} // namespace lumar
