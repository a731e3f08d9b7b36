#include "bench/tracking_sequences.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <functional>
#include <limits>
#include <memory>
#include <optional>
#include <random>

#include <opencv2/imgcodecs.hpp>

#include "bench/tracking_bench_scene.h"
#include "bench/tracking_scoring.h"
#include "core/error.h"
#include "core/json_output.h"
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
constexpr int kNoTarget = -2;  // no drawn pose scored (the photos: every tag has id 0)

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

// A sequence ready to run: its frames with their truth, and what a detector needs to know.
struct RenderedSequence {
    std::string name;
    CameraIntrinsics k;
    TagSizes sizes;
    std::optional<TagMap> board; // the tags form this [[maps]] board, its frame the world's
    int target = 0;              // the tag id whose drawn pose is scored, kMapTarget or kNoTarget
    std::vector<BenchFrame> frames;
    std::vector<Pose> targetTruth; // the target's true camera_from_marker (or _map) per frame
    std::vector<bool> still, panning;
};

// What a detector gives per frame: its detections and the pose it would draw the target with.
struct FrameResult {
    std::vector<TagDetection> detections;
    std::optional<Pose> drawn;
};

class SequenceDetector {
public:
    virtual ~SequenceDetector() = default;
    [[nodiscard]] virtual std::string name() const = 0;
    virtual void restart(const RenderedSequence& s) = 0;
    virtual void detect(const Image8& luma, int frame, FrameResult& out) = 0;
};

// lumar as `lumar render` runs it: the tracker with a [tracking] configuration, the board as a
// [[maps]] entry, the filtered pose at the frame's time.
class LumarSequenceDetector final : public SequenceDetector {
public:
    explicit LumarSequenceDetector(LumarVariant variant) : variant_(std::move(variant)) {}
    [[nodiscard]] std::string name() const override { return variant_.name; }
    void restart(const RenderedSequence& s) override
    {
        // A new tracker per sequence, as `lumar render` starts with one: built before timing.
        tracker_ = std::make_unique<TagTracker>(variant_.config, s.k, s.sizes);
        if (s.board)
            tracker_->setMaps({*s.board});
        tracked_ = TrackedPoses(variant_.config);
        target_ = s.target;
    }
    void detect(const Image8& luma, int frame, FrameResult& out) override
    {
        out.detections = tracker_->detect(luma);
        const std::vector<MapDetection> maps = tracker_->detectMaps(out.detections);
        const auto timestampNs = int64_t(std::llround(frame * 1e9 / kFps));
        tracked_.update(out.detections, maps, uint64_t(frame), timestampNs);
        out.drawn.reset();
        if (target_ == kNoTarget)
            return;
        const int key = target_ == kMapTarget ? TrackedPoses::mapKey(0) : target_;
        const auto used = tracked_.poseAt(key, uint64_t(frame), timestampNs);
        if (used)
            out.drawn = used->cameraFromMarker;
    }

private:
    LumarVariant variant_;
    std::unique_ptr<TagTracker> tracker_;
    TrackedPoses tracked_;
    int target_ = 0;
};

// The AprilTag library with its defaults, frame by frame (bench/tracking_scoring.h), the board
// solved from its tags by lumar's map solver; no filter.
class AprilTagSequenceDetector final : public SequenceDetector {
public:
    [[nodiscard]] std::string name() const override { return "apriltag"; }
    void restart(const RenderedSequence& s) override { sequence_ = &s; }
    void detect(const Image8& luma, int, FrameResult& out) override
    {
        const RenderedSequence& s = *sequence_;
        out.detections = library_.detect(luma, s.sizes, s.k);
        out.drawn.reset();
        if (s.board) {
            MapDetection map;
            if (solveMapPose(*s.board, out.detections, s.k, map))
                out.drawn = map.cameraFromMap;
        } else {
            for (const TagDetection& d : out.detections)
                if (d.id == s.target && d.hasPose)
                    out.drawn = d.cameraFromMarker;
        }
    }
    [[nodiscard]] std::string settings() const { return library_.settings(); }

private:
    AprilTagDefaults library_;
    const RenderedSequence* sequence_ = nullptr;
};

// Runs `detector` over `r` and scores it (ms per frame: this run's mean).
TrackingSequenceRow score(SequenceDetector& detector, const RenderedSequence& r)
{
    TrackingSequenceRow row;
    row.sequence = r.name;
    row.detector = detector.name();
    row.frames = int(r.frames.size());
    detector.restart(r);
    const size_t tagCount = r.frames.empty() ? 0 : r.frames[0].tags.size();
    struct TagState {
        bool wasVisible = true; // a tag visible from the first frame is no re-acquisition
        bool pending = false;
        int since = 0;
        std::array<std::vector<glm::dvec3>, 4> stillCorners; // found while still (z = 0)
    };
    std::vector<TagState> states(tagCount);
    std::vector<int> delays;
    std::vector<glm::dvec3> stillT, stillR;
    std::vector<double> cornerErrors;
    double lagSum = 0.0, lagMsSum = 0.0;
    int lagCount = 0;
    double seconds = 0.0, cpuSeconds = 0.0;
    // Corner jitter: the RMS over the still frames' corners of their distance from the mean of
    // the same corner of the same tag in the same still stretch (the camera may move between).
    double jitterSquares = 0.0;
    int jitterCount = 0;
    const auto flushJitter = [&](TagState& state) {
        for (std::vector<glm::dvec3>& corner : state.stillCorners) {
            if (corner.size() >= 2) {
                const double sd = standardDeviation(corner);
                jitterSquares += sd * sd * double(corner.size() - 1);
                jitterCount += int(corner.size() - 1);
            }
            corner.clear();
        }
    };
    FrameResult result;
    for (int f = 0; f < row.frames; ++f) {
        const BenchFrame& frame = r.frames[size_t(f)];
        const double wall0 = wallSeconds(), cpu0 = processCpuSeconds();
        detector.detect(frame.luma, f, result);
        cpuSeconds += processCpuSeconds() - cpu0;
        seconds += wallSeconds() - wall0;
        const FrameMatch match = matchDetections(frame.tags, result.detections);
        if (!r.still[size_t(f)])
            for (TagState& state : states)
                flushJitter(state);
        for (size_t t = 0; t < frame.tags.size(); ++t) {
            const BenchTagTruth& truth = frame.tags[t];
            TagState& state = states[t];
            const int index = match.detectionOf[t];
            const bool found = index >= 0;
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
                if (found) {
                    const TagDetection& d = result.detections[size_t(index)];
                    for (size_t c = 0; c < 4; ++c) {
                        cornerErrors.push_back(glm::length(d.corners[c] - truth.corners[c]));
                        if (r.still[size_t(f)])
                            state.stillCorners[c].push_back(glm::dvec3(d.corners[c], 0.0));
                    }
                }
            } else if (state.pending) {
                delays.push_back(state.since); // hidden again before it was found
                state.pending = false;
            }
            state.wasVisible = truth.visible;
        }
        if (result.drawn && !r.targetTruth.empty()) {
            const Pose& truth = r.targetTruth[size_t(f)];
            if (r.still[size_t(f)]) {
                stillT.push_back(result.drawn->t - truth.t);
                stillR.push_back(rotationVector(truth.R, result.drawn->R));
            }
            if (r.panning[size_t(f)] && f > 0) {
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
    for (TagState& state : states) {
        if (state.pending)
            delays.push_back(state.since);
        flushJitter(state);
    }
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
    row.cornerMeanPx = mean(cornerErrors);
    row.cornerJitterPx = jitterCount > 0 ? std::sqrt(jitterSquares / jitterCount) : kNaN;
    row.msPerFrame = 1000.0 * seconds / std::max(1, row.frames);
    row.cpuMsPerFrame = 1000.0 * cpuSeconds / std::max(1, row.frames);
    return row;
}

RenderedSequence renderSequence(const TrackingBenchScene& scene, const Sequence& s, size_t index, uint64_t seed)
{
    RenderedSequence r;
    r.name = s.name;
    r.k = scene.intrinsics();
    for (const BenchTag& tag : s.scene.tags)
        r.sizes.byId[tag.id] = tag.size;
    if (s.board)
        r.board = boardMap(s);
    r.target = s.target;
    r.frames.resize(size_t(s.frames));
    for (int f = 0; f < s.frames; ++f) {
        BenchCondition c = s.scene;
        c.covered = s.covered(f);
        c.motionBlurPx = s.blurPx(f);
        const Pose cameraFromWorld = s.cameraFromWorld(f);
        scene.renderView(c, cameraFromWorld, seed * 1000003ULL + index * 1009ULL + uint64_t(f), r.frames[size_t(f)]);
        if (s.target == kMapTarget) {
            r.targetTruth.push_back(cameraFromWorld); // the board's frame is the world's
        } else {
            for (const BenchTagTruth& t : r.frames[size_t(f)].tags)
                if (t.id == s.target)
                    r.targetTruth.push_back(t.cameraFromMarker);
        }
        r.still.push_back(s.still(f));
        r.panning.push_back(s.panning(f));
    }
    return r;
}

// The library's test photos (MANIFEST.md of the shared data): their names, in report order.
constexpr std::array<const char*, 3> kPhotos{"33369213973_9d9bb4cc96_c", "34085369442_304b6bafd9_c",
                                             "34139872896_defdb2f8d9_c"};
// Sensor noise added to each frame of a photo (code values): the photos are one exposure each.
constexpr double kPhotoNoiseSigma = 2.0;

// One line per tag: "ID, (x0 y0), (x1 y1), (x2 y2), (x3 y3)", the library's pixel convention.
std::vector<BenchTagTruth> readRecordedTags(const std::filesystem::path& path)
{
    std::ifstream in(path);
    if (!in)
        throw InputError(path.string() + ": cannot read the recorded detections");
    std::vector<BenchTagTruth> tags;
    std::string line;
    while (std::getline(in, line)) {
        if (line.empty())
            continue;
        BenchTagTruth t;
        auto& c = t.corners;
        if (std::sscanf(line.c_str(), "%d, (%lf %lf), (%lf %lf), (%lf %lf), (%lf %lf)", &t.id, &c[0].x, &c[0].y,
                        &c[1].x, &c[1].y, &c[2].x, &c[2].y, &c[3].x, &c[3].y) != 9)
            throw InputError(path.string() + ": not a recorded detection: '" + line + "'");
        for (glm::dvec2& corner : c)
            corner -= glm::dvec2(0.5); // into OpenCV's pixel convention
        t.size = 0.16;
        t.visible = true;
        tags.push_back(t);
    }
    return tags;
}

// The photos as still sequences; none (and a note) when `dir` does not hold them.
std::vector<RenderedSequence> loadPhotoSequences(const std::filesystem::path& dataDir, int frames, uint64_t seed,
                                                 std::vector<std::string>& notes)
{
    std::vector<RenderedSequence> list;
    const std::filesystem::path dir = dataDir / "apriltag" / "real";
    std::error_code error;
    if (dataDir.empty() || !std::filesystem::exists(dir / (std::string(kPhotos[0]) + ".jpg"), error)) {
        notes.push_back("photo sequences skipped: no AprilTag test photos under '" + dir.string() +
                        "' (--data or LUMAR_DATA_DIR: the shared data folder)");
        return list;
    }
    for (size_t i = 0; i < kPhotos.size(); ++i) {
        const std::filesystem::path jpeg = dir / (std::string(kPhotos[i]) + ".jpg");
        const cv::Mat gray = cv::imread(jpeg.string(), cv::IMREAD_GRAYSCALE);
        if (gray.empty())
            throw InputError(jpeg.string() + ": cannot decode the photo");
        RenderedSequence r;
        r.name = "photo_" + std::string(kPhotos[i]).substr(0, 11);
        // The library's pose test assumes these; no calibration exists for the photos.
        r.k.width = gray.cols;
        r.k.height = gray.rows;
        r.k.fx = r.k.fy = 600.0;
        r.k.cx = gray.cols / 2.0;
        r.k.cy = gray.rows / 2.0;
        r.sizes.fallback = 0.16;
        r.target = kNoTarget;
        const std::vector<BenchTagTruth> truth = readRecordedTags(dir / (std::string(kPhotos[i]) + ".txt"));
        std::mt19937_64 random(seed * 7919ULL + i);
        std::normal_distribution<double> noise(0.0, kPhotoNoiseSigma);
        for (int f = 0; f < frames; ++f) {
            BenchFrame frame;
            frame.luma.width = gray.cols;
            frame.luma.height = gray.rows;
            frame.luma.channels = 1;
            frame.luma.data.resize(size_t(gray.cols) * size_t(gray.rows));
            for (int y = 0; y < gray.rows; ++y)
                for (int x = 0; x < gray.cols; ++x)
                    frame.luma.data[size_t(y) * size_t(gray.cols) + size_t(x)] =
                        uint8_t(std::clamp(std::lround(gray.at<uint8_t>(y, x) + noise(random)), 0L, 255L));
            frame.tags = truth;
            r.frames.push_back(std::move(frame));
            r.still.push_back(true);
            r.panning.push_back(false);
        }
        list.push_back(std::move(r));
    }
    notes.push_back("photo_*: the AprilTag library's test photos (" + dir.string() +
                    "; 799x533, 12, 25 and 10 tags, all id 0), each " + std::to_string(frames) +
                    " frames of the photo with fresh Gaussian noise (sigma " + fixed(kPhotoNoiseSigma, 1) +
                    "), scored against the corners the library recorded (quad_decimate 1); fx = fy = 600 px, "
                    "0.16 m tags as the library's pose test assumes; corner jitter over the frames");
    return list;
}

} // namespace

LumarVariant parseLumarVariant(const std::string& text)
{
    LumarVariant variant;
    const size_t colon = text.find(':');
    variant.name = text.substr(0, colon);
    if (variant.name.empty())
        throw InputError("--lumar '" + text + "': needs a name, e.g. 'coarse:coarse_every=1'");
    std::string settings = colon == std::string::npos ? std::string() : text.substr(colon + 1);
    std::replace(settings.begin(), settings.end(), ',', '\n');
    variant.config = parseConfig("[tracking]\n" + settings + "\n", "--lumar " + variant.name, ".").tracking;
    // One thread unless given, as the library's defaults run.
    const bool threadsGiven = ("\n" + settings).find("\nthreads") != std::string::npos;
    if (!threadsGiven)
        variant.config.threads = 1;
    return variant;
}

TrackingSequencesReport runTrackingSequences(const TrackingSequencesOptions& options)
{
    if (options.rounds < 1 || options.rounds > 100)
        throw InputError("tracking sequences: rounds must be in [1, 100], got " + std::to_string(options.rounds));
    if (options.photoFrames < 2 || options.photoFrames > 1000)
        throw InputError("tracking sequences: photo frames must be in [2, 1000], got " +
                         std::to_string(options.photoFrames));
    TrackingSequencesReport report;
    report.options = options;
    const TrackingBenchScene scene(options.width, options.height, options.seed);
    static const std::vector<Sequence> sequences = makeSequences();

    // Every frame rendered (or decoded) once, before any timing.
    std::vector<RenderedSequence> rendered;
    for (size_t i = 0; i < sequences.size(); ++i)
        rendered.push_back(renderSequence(scene, sequences[i], i, options.seed));
    for (RenderedSequence& r : loadPhotoSequences(options.dataDir, options.photoFrames, options.seed, report.notes))
        rendered.push_back(std::move(r));

    std::vector<LumarVariant> variants = options.lumar;
    if (variants.empty()) {
        variants.push_back({"lumar", TrackingConfig{}});
        variants.back().config.threads = 1;
        variants.push_back({"lumar_2threads", TrackingConfig{}});
        variants.back().config.threads = 2;
    }
    std::vector<std::unique_ptr<SequenceDetector>> detectors;
    for (const LumarVariant& v : variants)
        detectors.push_back(std::make_unique<LumarSequenceDetector>(v));
    auto library = std::make_unique<AprilTagSequenceDetector>();
    const std::string librarySettings = library->settings();
    detectors.push_back(std::move(library));

    // rows[sequence][detector], scored in the first round; times of every round.
    std::vector<std::vector<TrackingSequenceRow>> rows(rendered.size(),
                                                       std::vector<TrackingSequenceRow>(detectors.size()));
    std::vector<std::vector<std::vector<double>>> times(rendered.size(),
                                                        std::vector<std::vector<double>>(detectors.size()));
    auto cpuTimes = times;
    for (int round = 0; round < options.rounds; ++round)
        for (size_t i = 0; i < rendered.size(); ++i)
            for (size_t n = 0; n < detectors.size(); ++n) {
                // Odd rounds run the detectors in the reverse order: neither always goes first.
                const size_t d = round % 2 == 0 ? n : detectors.size() - 1 - n;
                TrackingSequenceRow row = score(*detectors[d], rendered[i]);
                times[i][d].push_back(row.msPerFrame);
                cpuTimes[i][d].push_back(row.cpuMsPerFrame);
                if (round == 0)
                    rows[i][d] = std::move(row);
            }
    for (size_t i = 0; i < rendered.size(); ++i)
        for (size_t d = 0; d < detectors.size(); ++d) {
            rows[i][d].msPerFrame = median(times[i][d]);
            rows[i][d].cpuMsPerFrame = median(cpuTimes[i][d]);
            report.rows.push_back(rows[i][d]);
        }
    std::string lumarNote = "lumar variants, each a [tracking] configuration with the pose drawn at the frame's time:";
    for (const LumarVariant& v : variants) {
        const TrackingConfig& c = v.config;
        lumarNote += " " + v.name + " (threads " + std::to_string(c.threads) + ", roi " + std::to_string(int(c.roi)) +
                     ", full frame every " + std::to_string(c.fullFrameEvery) + ", coarse every " +
                     std::to_string(c.coarseEvery) + " at quad_decimate " + fixed(c.coarseDecimate, 1) +
                     ", max_bit_errors " + std::to_string(c.maxBitErrors) + ");";
    }
    report.notes.push_back(lumarNote);
    report.notes.push_back("apriltag: the library's defaults (" + librarySettings +
                           "), raw IPPE poses, the board by lumar's map solver");
    report.notes.push_back("jitter and lag: of the target's drawn pose (board_4: the board's; others: tag 7, or tag 0 "
                           "in leave_reenter and fast_pan), against the exact pose; corner jitter: of the found "
                           "corners on still frames; ms and CPU ms (the process's CPU time: a helper thread counts): "
                           "median of " +
                           std::to_string(options.rounds) + " interleaved rounds");
    return report;
}

std::string trackingSequencesMarkdown(const TrackingSequencesReport& report)
{
    MarkdownTable table({"sequence", "detector", "frames", "visible", "found", "recall", "re-acq.", "delay mean",
                         "delay max", "jitter mm", "jitter deg", "lag mm", "lag ms", "corner px", "corner jitter px",
                         "ms/frame", "CPU ms/frame"},
                        2);
    for (const TrackingSequenceRow& r : report.rows)
        table.add({r.sequence, r.detector, std::to_string(r.frames), std::to_string(r.visibleTags),
                   std::to_string(r.found), fixed(r.recall, 3), std::to_string(r.reacquisitions),
                   fixed(r.reacquireMeanFrames, 2), r.reacquisitions > 0 ? std::to_string(r.reacquireMaxFrames) : "–",
                   fixed(r.jitterMm, 2), fixed(r.jitterDeg, 3), fixed(r.lagMm, 1), fixed(r.lagMs, 1),
                   fixed(r.cornerMeanPx, 3), fixed(r.cornerJitterPx, 3), fixed(r.msPerFrame, 2),
                   fixed(r.cpuMsPerFrame, 2)});
    std::string out = table.str() + "\n";
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
                        {"corner_mean_px", jsonSignificant(r.cornerMeanPx, 6)},
                        {"corner_jitter_px", jsonSignificant(r.cornerJitterPx, 6)},
                        {"ms_per_frame", jsonSignificant(r.msPerFrame, 6)},
                        {"cpu_ms_per_frame", jsonSignificant(r.cpuMsPerFrame, 6)}});
    const Json j = {{"width", report.options.width},   {"height", report.options.height}, {"seed", report.options.seed},
                    {"rounds", report.options.rounds}, {"rows", std::move(rows)},         {"notes", report.notes}};
    return jsonLine(j) + "\n";
}

} // namespace lumar
