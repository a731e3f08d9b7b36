#include "tracking/tag_tracker.h"

#include <algorithm>
#include <cmath>
#include <string>

#include <apriltag/apriltag.h>

#include "core/error.h"
#include "core/log.h"
#include "tracking/apriltag_family.h"
#include "tracking/tag_map.h"

namespace lumar {
namespace {

struct DetectorDeleter {
    void operator()(apriltag_detector_t* detector) const { apriltag_detector_destroy(detector); }
};
using DetectorPtr = std::unique_ptr<apriltag_detector_t, DetectorDeleter>;

// apriltag_detections_destroy frees the array and every detection in it.
struct DetectionsDeleter {
    void operator()(zarray_t* detections) const { apriltag_detections_destroy(detections); }
};
using DetectionsPtr = std::unique_ptr<zarray_t, DetectionsDeleter>;

// A tag's last pose older than this many frames says little about its orientation now.
constexpr uint64_t kPreviousPoseFrames = 15;

// Below this the library's 4x4 threshold tiles degenerate, and no tag fits anyway.
constexpr int kMinImageSide = 8;
constexpr int kMaxThreads = 64;

// See CMakeLists.txt: older libraries crash at random with more than one thread.
#ifdef LUMAR_APRILTAG_THREADS_UNSAFE
constexpr bool kLibraryThreadsAreSafe = false;
#else
constexpr bool kLibraryThreadsAreSafe = true;
#endif

void validate(const TrackingConfig& config, const CameraIntrinsics& k, const TagSizes& sizes)
{
    if (!(config.quadDecimate >= 1.0 && config.quadDecimate <= 16.0))
        throw InputError("tracking: quad_decimate must be in [1, 16], got " + std::to_string(config.quadDecimate));
    if (!std::isfinite(config.quadSigma) || std::abs(config.quadSigma) > 16.0)
        throw InputError("tracking: quad_sigma must be in [-16, 16], got " + std::to_string(config.quadSigma));
    if (!(config.decodeSharpening >= 0.0 && config.decodeSharpening <= 16.0))
        throw InputError("tracking: decode_sharpening must be in [0, 16], got " +
                         std::to_string(config.decodeSharpening));
    if (config.threads < 1 || config.threads > kMaxThreads)
        throw InputError("tracking: threads must be in [1, " + std::to_string(kMaxThreads) + "], got " +
                         std::to_string(config.threads));
    if (k.width <= 0 || k.height <= 0 || !(k.fx > 0.0) || !(k.fy > 0.0) || !std::isfinite(k.fx) ||
        !std::isfinite(k.fy) || !std::isfinite(k.cx) || !std::isfinite(k.cy))
        throw InputError("tracking: camera intrinsics need a positive image size and focal lengths");
    const auto validSize = [](double s) { return std::isfinite(s) && s >= 0.0; };
    if (!validSize(sizes.fallback))
        throw InputError("tracking: the default tag size must be a finite length >= 0");
    for (const auto& [id, size] : sizes.byId)
        if (!validSize(size))
            throw InputError("tracking: the size of tag " + std::to_string(id) + " must be a finite length >= 0");
}

// With quad_decimate 1 and a blur kernel wider than one pixel the library blurs (or
// sharpens) its input in place; only then does it need a copy of our const frame.
bool libraryWritesInput(const TrackingConfig& config)
{
    if (float(config.quadDecimate) > 1.0f) // compared as the library stores it
        return false;
    int kernel = int(4.0f * std::abs(float(config.quadSigma)));
    if (kernel % 2 == 0)
        ++kernel;
    return kernel > 1;
}

} // namespace

struct TagTracker::Impl {
    // Declared before the detector so that it outlives it: the detector only borrows it.
    AprilTagFamilyPtr family;
    DetectorPtr detector;
    CameraIntrinsics intrinsics;
    TagSizes sizes;
    std::vector<TagMap> maps;
    bool copyInput = false;
    std::vector<uint8_t> scratch; // the copy the library may modify, reused every frame
    // Region-of-interest search around the last detections (DESIGN.md §5).
    bool roi = false;
    int fullFrameEvery = 1;
    int roiAlignment = 8;
    int framesSinceFullSearch = 0;
    std::vector<TagDetection> last;

    // The last pose of each tag id, to choose between IPPE's two solutions when they tie.
    struct LastPose {
        Pose pose;
        uint64_t frame = 0;
    };
    std::map<int, LastPose> lastPoses;
    uint64_t frameCount = 0;

    // Solves the pose of every detection whose size is known.
    void solvePoses(std::vector<TagDetection>& detections);

    // Detects in the rectangle [x0, x1) x [y0, y1) of `pixels` (row stride `stride`) and
    // appends to `out` with corners in full-image coordinates.
    void detectIn(uint8_t* pixels, int stride, int x0, int y0, int x1, int y1, std::vector<TagDetection>& out);
};

namespace {

// The search window around the last detections: their bounding box grown by its own size
// (a tag moving fast between frames stays inside), at least kMinRoiMargin pixels each side.
constexpr double kMinRoiMargin = 48.0;

struct Window {
    int x0, y0, x1, y1;
};

// `align`: the window's origin is a multiple of it, so the library's decimation grid and its
// threshold tiles (4x4 decimated pixels) fall exactly where a full-frame search puts them and
// both searches see the same pixels the same way.
Window searchWindow(const std::vector<TagDetection>& last, int width, int height, int align)
{
    double minX = 1e9, minY = 1e9, maxX = -1e9, maxY = -1e9;
    for (const TagDetection& d : last)
        for (const glm::dvec2& c : d.corners) {
            minX = std::min(minX, c.x);
            minY = std::min(minY, c.y);
            maxX = std::max(maxX, c.x);
            maxY = std::max(maxY, c.y);
        }
    const double margin = std::max(kMinRoiMargin, 0.5 * std::max(maxX - minX, maxY - minY));
    const auto alignDown = [align](int v) { return v / align * align; };
    return {alignDown(std::clamp(int(std::floor(minX - margin)), 0, width)),
            alignDown(std::clamp(int(std::floor(minY - margin)), 0, height)),
            std::clamp(int(std::ceil(maxX + margin)), 0, width), std::clamp(int(std::ceil(maxY + margin)), 0, height)};
}

// A tag cut by the window's edge can still decode, with a wrong quad; such a result is not
// trusted (the caller searches the full frame). Edges that are the image's own are fine.
constexpr double kWindowEdgeClearance = 4.0;

bool wellInside(const std::vector<TagDetection>& detections, const Window& w, int width, int height)
{
    for (const TagDetection& d : detections)
        for (const glm::dvec2& c : d.corners) {
            if ((w.x0 > 0 && c.x < w.x0 + kWindowEdgeClearance) || (w.y0 > 0 && c.y < w.y0 + kWindowEdgeClearance) ||
                (w.x1 < width && c.x > w.x1 - kWindowEdgeClearance) ||
                (w.y1 < height && c.y > w.y1 - kWindowEdgeClearance))
                return false;
        }
    return true;
}

// By id, then left to right for repeated ids.
void sortDetections(std::vector<TagDetection>& detections)
{
    std::sort(detections.begin(), detections.end(), [](const TagDetection& a, const TagDetection& b) {
        if (a.id != b.id)
            return a.id < b.id;
        return a.corners[0].x < b.corners[0].x;
    });
}

bool sameIds(const std::vector<TagDetection>& a, const std::vector<TagDetection>& b)
{
    return std::equal(a.begin(), a.end(), b.begin(), b.end(),
                      [](const TagDetection& x, const TagDetection& y) { return x.id == y.id; });
}

} // namespace

TagTracker::TagTracker(const TrackingConfig& config, const CameraIntrinsics& intrinsics, TagSizes sizes)
    : impl_(std::make_unique<Impl>())
{
    validate(config, intrinsics, sizes);
    impl_->family = createAprilTagFamily(config.family);
    impl_->detector.reset(apriltag_detector_create());
    if (!impl_->detector)
        throw RuntimeError("cannot create the AprilTag detector");
    apriltag_detector_t& td = *impl_->detector;
    td.quad_decimate = float(config.quadDecimate);
    td.quad_sigma = float(config.quadSigma);
    td.refine_edges = config.refineEdges;
    td.decode_sharpening = config.decodeSharpening;
    td.nthreads = kLibraryThreadsAreSafe ? config.threads : 1;
    if (td.nthreads != config.threads) {
        LUMAR_LOG(Tracking, Info) << "libapriltag " << LUMAR_APRILTAG_VERSION
                                  << " can crash with several threads (fixed in 3.4.3): detecting on 1 thread, not "
                                  << config.threads;
    }
    const int bits = correctableBitsFor(*impl_->family);
    apriltag_detector_add_family_bits(&td, impl_->family.get(), bits);

    impl_->intrinsics = intrinsics;
    impl_->sizes = std::move(sizes);
    impl_->copyInput = libraryWritesInput(config);
    impl_->roi = config.roi;
    impl_->fullFrameEvery = std::max(1, config.fullFrameEvery);
    impl_->roiAlignment = 4 * int(std::ceil(config.quadDecimate));
    LUMAR_LOG(Tracking, Info) << "AprilTag " << config.family << " (corrects " << bits << " bits), quad_decimate "
                              << config.quadDecimate << ", quad_sigma " << config.quadSigma << ", refine_edges "
                              << config.refineEdges << ", " << td.nthreads << " threads";
}

TagTracker::~TagTracker() = default;
TagTracker::TagTracker(TagTracker&&) noexcept = default;
TagTracker& TagTracker::operator=(TagTracker&&) noexcept = default;

void TagTracker::setMaps(std::vector<TagMap> maps)
{
    for (const TagMap& map : maps)
        for (const TagMapTag& tag : map.tags) {
            if (!(std::isfinite(tag.size) && tag.size > 0.0))
                throw InputError("tracking: map '" + map.name + "': tag " + std::to_string(tag.id) +
                                 " needs a positive size");
            const auto [it, inserted] = impl_->sizes.byId.try_emplace(tag.id, tag.size);
            if (!inserted && it->second != tag.size)
                throw InputError("tracking: map '" + map.name + "': tag " + std::to_string(tag.id) + " has size " +
                                 std::to_string(tag.size) + " but is also known with size " +
                                 std::to_string(it->second));
        }
    impl_->maps = std::move(maps);
}

std::vector<MapDetection> TagTracker::detectMaps(const std::vector<TagDetection>& detections) const
{
    std::vector<MapDetection> result;
    for (size_t i = 0; i < impl_->maps.size(); ++i) {
        MapDetection map;
        if (solveMapPose(impl_->maps[i], detections, impl_->intrinsics, map)) {
            map.index = int(i);
            result.push_back(std::move(map));
        }
    }
    return result;
}

const CameraIntrinsics& TagTracker::intrinsics() const
{
    return impl_->intrinsics;
}

std::vector<TagDetection> TagTracker::detect(const Image8& luma)
{
    const CameraIntrinsics& k = impl_->intrinsics;
    if (luma.channels != 1 || luma.width < 0 || luma.height < 0 ||
        luma.data.size() != size_t(luma.width) * size_t(luma.height))
        throw InputError("tracking: expected an 8-bit single-channel image, got " + std::to_string(luma.channels) +
                         " channels");
    if (luma.width != k.width || luma.height != k.height)
        throw InputError("tracking: image is " + std::to_string(luma.width) + "x" + std::to_string(luma.height) +
                         " but the camera intrinsics are for " + std::to_string(k.width) + "x" +
                         std::to_string(k.height));
    std::vector<TagDetection> result;
    if (luma.width < kMinImageSide || luma.height < kMinImageSide)
        return result;

    // The library takes a mutable buffer but only reads it, except in the case above.
    uint8_t* pixels = const_cast<uint8_t*>(luma.data.data());
    if (impl_->copyInput) {
        impl_->scratch.assign(luma.data.begin(), luma.data.end());
        pixels = impl_->scratch.data();
    }
    // Search near the last detections; fall back to the full frame when a tag went missing
    // there, and search the full frame regularly anyway so new tags are found.
    bool searched = false;
    if (impl_->roi && !impl_->last.empty() && ++impl_->framesSinceFullSearch < impl_->fullFrameEvery) {
        const Window w = searchWindow(impl_->last, luma.width, luma.height, impl_->roiAlignment);
        if (w.x1 - w.x0 >= kMinImageSide && w.y1 - w.y0 >= kMinImageSide) {
            impl_->detectIn(pixels, luma.width, w.x0, w.y0, w.x1, w.y1, result);
            sortDetections(result);
            searched = sameIds(result, impl_->last) && wellInside(result, w, luma.width, luma.height);
        }
    }
    if (!searched) {
        result.clear();
        impl_->framesSinceFullSearch = 0;
        impl_->detectIn(pixels, luma.width, 0, 0, luma.width, luma.height, result);
    }
    sortDetections(result);
    impl_->solvePoses(result);
    impl_->last = result;
    return result;
}

void TagTracker::Impl::solvePoses(std::vector<TagDetection>& detections)
{
    ++frameCount;
    for (size_t i = 0; i < detections.size(); ++i) {
        TagDetection& d = detections[i];
        const double size = sizes.of(d.id);
        if (!(size > 0.0))
            continue;
        // An id seen twice in one frame has no single previous pose (detections are sorted).
        const bool unique =
            (i == 0 || detections[i - 1].id != d.id) && (i + 1 == detections.size() || detections[i + 1].id != d.id);
        const auto previous = unique ? lastPoses.find(d.id) : lastPoses.end();
        const bool recent = previous != lastPoses.end() && frameCount - previous->second.frame <= kPreviousPoseFrames;
        TagPoseSolution solution;
        d.hasPose = solveTagPose(d.corners, size, intrinsics, solution, recent ? &previous->second.pose : nullptr);
        if (!d.hasPose) {
            LUMAR_LOG(Tracking, Debug) << "tag " << d.id << ": no plausible pose";
            continue;
        }
        d.cameraFromMarker = solution.cameraFromMarker;
        d.reprojectionErrorPx = solution.rmsErrorPx;
        d.ambiguityRatio = solution.ambiguityRatio;
        if (unique)
            lastPoses[d.id] = {d.cameraFromMarker, frameCount};
    }
}

void TagTracker::Impl::detectIn(uint8_t* pixels, int stride, int x0, int y0, int x1, int y1,
                                std::vector<TagDetection>& out)
{
    image_u8_t image{x1 - x0, y1 - y0, stride, pixels + size_t(y0) * size_t(stride) + size_t(x0)};
    const DetectionsPtr detections(apriltag_detector_detect(detector.get(), &image));
    if (!detections)
        throw RuntimeError("AprilTag detection failed");

    const int count = zarray_size(detections.get());
    out.reserve(out.size() + size_t(count));
    for (int i = 0; i < count; ++i) {
        apriltag_detection_t* det = nullptr;
        zarray_get(detections.get(), i, &det);
        TagDetection d;
        d.id = det->id;
        d.hamming = det->hamming;
        d.decisionMargin = det->decision_margin;
        // The library's pixel (0,0) covers [0,1]^2, ours [-0.5,0.5]^2 (DESIGN.md §5).
        for (int c = 0; c < 4; ++c)
            d.corners[size_t(c)] = {det->p[c][0] - 0.5 + x0, det->p[c][1] - 0.5 + y0};
        out.push_back(d);
    }
}

} // namespace lumar
