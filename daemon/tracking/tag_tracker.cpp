#include "tracking/tag_tracker.h"

#include <algorithm>
#include <cmath>
#include <set>
#include <string>

#include <apriltag/apriltag.h>

#include "core/error.h"
#include "core/helper_thread.h"
#include "core/log.h"
#include "tracking/followed_tags.h"
#include "tracking/scene_families.h"
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

// While every tag of the scene (the sized tags and the maps' tags, no default size) was found
// on the last frame, the searches for new tags run this many times less often (only every
// 6th scheduled one is made): all they could still find is a tag nothing is placed on or a
// second copy of a scene's id. On car.toml they
// took ~3.4 of the detection thread's ~7 ms per frame (a decimate-2 full frame, ~20 ms, every
// 10 frames; a coarse one, ~4 ms, every 3), CPU the renderer shares. A scene's tag that goes
// missing brings the full-frame search at once, as before, and while one is missing the
// searches keep their configured pace, so re-acquisition is as quick as it was.
constexpr int kAllHeldSearchSlowdown = 6;

// Below this the library's 4x4 threshold tiles degenerate, and no tag fits anyway.
constexpr int kMinImageSide = 8;
constexpr int kMaxThreads = 64;

// See CMakeLists.txt: older libraries crash at random with more than one thread.
#ifdef LUMAR_APRILTAG_THREADS_UNSAFE
constexpr bool kLibraryThreadsAreSafe = false;
#else
constexpr bool kLibraryThreadsAreSafe = true;
#endif

void validateIntrinsics(const CameraIntrinsics& k)
{
    if (k.width <= 0 || k.height <= 0 || !(k.fx > 0.0) || !(k.fy > 0.0) || !std::isfinite(k.fx) ||
        !std::isfinite(k.fy) || !std::isfinite(k.cx) || !std::isfinite(k.cy))
        throw InputError("tracking: camera intrinsics need a positive image size and focal lengths");
}

void validate(const TrackingConfig& config, const CameraIntrinsics& k, const TagSizes& sizes)
{
    if (!(config.quadDecimate >= 1.0 && config.quadDecimate <= 16.0))
        throw InputError("tracking: quad_decimate must be in [1, 16], got " + std::to_string(config.quadDecimate));
    if (!std::isfinite(config.quadSigma) || std::abs(config.quadSigma) > 16.0)
        throw InputError("tracking: quad_sigma must be in [-16, 16], got " + std::to_string(config.quadSigma));
    if (!(config.decodeSharpening >= 0.0 && config.decodeSharpening <= 16.0))
        throw InputError("tracking: decode_sharpening must be in [0, 16], got " +
                         std::to_string(config.decodeSharpening));
    if (!(config.coarseDecimate >= 1.0 && config.coarseDecimate <= 16.0))
        throw InputError("tracking: coarse_decimate must be in [1, 16], got " + std::to_string(config.coarseDecimate));
    if (config.coarseEvery < 0)
        throw InputError("tracking: coarse_every must be >= 0, got " + std::to_string(config.coarseEvery));
    if (config.maxBitErrors < 0 || config.maxBitErrors > 2)
        throw InputError("tracking: max_bit_errors must be in [0, 2], got " + std::to_string(config.maxBitErrors));
    if (config.threads < 1 || config.threads > kMaxThreads)
        throw InputError("tracking: threads must be in [1, " + std::to_string(kMaxThreads) + "], got " +
                         std::to_string(config.threads));
    validateIntrinsics(k);
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

DetectorPtr createDetector(const TrackingConfig& config, const SceneFamilies& families, int threads,
                           double quadDecimate)
{
    DetectorPtr detector(apriltag_detector_create());
    if (!detector)
        throw RuntimeError("cannot create the AprilTag detector");
    apriltag_detector_t& td = *detector;
    td.quad_decimate = float(quadDecimate);
    td.quad_sigma = float(config.quadSigma);
    td.refine_edges = config.refineEdges;
    td.decode_sharpening = config.decodeSharpening;
    td.nthreads = threads;
    families.addTo(td);
    return detector;
}

} // namespace

struct TagTracker::Impl {
    // Declared before the detectors so that it outlives them: they only borrow it. All
    // detectors share it: the library builds each family's decoding table once (at the
    // first apriltag_detector_add_family_bits, before any detection) and only reads it while
    // detecting; the first detector destroyed frees it, the others then find nothing to free.
    // The detectors are made at the first detect(), once setMaps() has named the maps' tags:
    // the families depend on the scene's ids (scene_families.h).
    std::unique_ptr<SceneFamilies> families;
    DetectorPtr detector;
    // With threads >= 2, a second detector and a helper thread search half of the followed
    // tags' windows in parallel (DESIGN.md §5). Each detector runs its library calls with
    // nthreads 1 on its own thread, so the library's worker pool, which crashes before 3.4.3,
    // is never used by them; two detector instances share no mutable state (libapriltag
    // 3.3.0's sources: all state lives in apriltag_detector_t and per-call allocations, the
    // family's decoding table is read only, and the only globals are the families' constant
    // code tables and random() in debug output).
    DetectorPtr second;
    std::unique_ptr<HelperThread> helper;
    // With coarse_every > 0: the coarse search's detector (coarse_decimate, one thread; the
    // family's table is shared, so it costs a few hundred bytes).
    DetectorPtr coarse;
    int coarseEvery = 0;
    int framesSinceCoarse = 0;
    TrackingConfig config;
    CameraIntrinsics intrinsics;
    TagSizes sizes;
    std::vector<TagMap> maps;
    bool copyInput = false;
    std::vector<uint8_t> scratch; // the copy the library may modify, reused every frame
    // Region-of-interest search around the followed tags (DESIGN.md §5).
    bool roi = false;
    int fullFrameEvery = 1;
    int roiAlignment = 8;
    int framesSinceFullSearch = 0;
    // Scheduled full-frame and coarse searches skipped in a row (kAllHeldSearchSlowdown).
    int fullSearchesSkipped = 0;
    int coarseSearchesSkipped = 0;
    // The scene's ids (sorted), set with the detectors; empty with a default size, when any
    // id is posed and so every tag in view counts.
    std::vector<int> sceneIds;
    FollowedTags followed{0, 0, 8};
    std::vector<int> lastIds;              // the ids of the last frame's detections, sorted, copies repeated
    std::vector<SearchWindow> lastWindows; // the last frame's windows (searchedWindows())

    // The maps solved from the last frame's detections (with roi and maps): they predict
    // where the maps' unseen tags are, and detectMaps() returns them without solving again.
    std::vector<TagDetection> mapsInput;
    std::vector<MapDetection> mapsResult;
    bool mapsValid = false;

    // The last pose of each tag id, to choose between IPPE's two solutions when they tie.
    struct LastPose {
        Pose pose;
        uint64_t frame = 0;
    };
    std::map<int, LastPose> lastPoses;
    uint64_t frameCount = 0;
    SearchCounts counts;

    void forgetHistory();
    // The scene's ids (the sized tags and the maps' tags; none when every tag is posed by a
    // fallback size), their families and the detectors, unless made already.
    void makeDetectors();
    void dropDetectors();
    // Every id of the scene found on the last frame (see kAllHeldSearchSlowdown).
    [[nodiscard]] bool sceneHeld() const;
    // Solves the pose of every detection whose size is known.
    void solvePoses(std::vector<TagDetection>& detections);
    [[nodiscard]] std::vector<MapDetection> solveMaps(const std::vector<TagDetection>& detections) const;
    // Searches the followed tags' windows; false when the result cannot stand for a
    // full-frame search (a detection cut by a window's edge, a tag of the last frame missing).
    bool searchWindows(uint8_t* pixels, int width, int height, std::vector<TagDetection>& out);
    // The coarse search of the whole frame: true when it finds a tag that `windowResult` (the
    // windows' detections) lacks, which then brings a full-frame search.
    bool coarseFindsMore(uint8_t* pixels, int width, int height, const std::vector<TagDetection>& windowResult);
    // Detects in `windows` on both detectors at once (each window on one), the results per window.
    void searchInParallel(uint8_t* pixels, int stride, const std::vector<SearchWindow>& windows,
                          std::vector<std::vector<TagDetection>>& found);
    // After a frame: follows its tags, and the unseen tags of the maps it shows.
    void follow(const std::vector<TagDetection>& detections);

    // Detects in the rectangle [x0, x1) x [y0, y1) of `pixels` (row stride `stride`) and
    // appends to `out` with corners in full-image coordinates.
    void detectIn(apriltag_detector_t& td, uint8_t* pixels, int stride, const SearchWindow& w,
                  std::vector<TagDetection>& out) const;
};

namespace {

// By id, then left to right for repeated ids.
void sortDetections(std::vector<TagDetection>& detections)
{
    std::sort(detections.begin(), detections.end(), [](const TagDetection& a, const TagDetection& b) {
        if (a.id != b.id)
            return a.id < b.id;
        return a.corners[0].x < b.corners[0].x;
    });
}

bool sameDetections(const std::vector<TagDetection>& a, const std::vector<TagDetection>& b)
{
    return std::equal(a.begin(), a.end(), b.begin(), b.end(), [](const TagDetection& x, const TagDetection& y) {
        return x.id == y.id && x.corners == y.corners && x.hasPose == y.hasPose;
    });
}

} // namespace

TagTracker::TagTracker(const TrackingConfig& config, const CameraIntrinsics& intrinsics, TagSizes sizes)
    : impl_(std::make_unique<Impl>())
{
    validate(config, intrinsics, sizes);
    (void)createAprilTagFamily(config.family); // an unknown name is bad input now, not at the first frame
    impl_->config = config;
    impl_->copyInput = libraryWritesInput(config);
    impl_->intrinsics = intrinsics;
    impl_->sizes = std::move(sizes);
    impl_->roi = config.roi;
    impl_->fullFrameEvery = std::max(1, config.fullFrameEvery);
    impl_->roiAlignment = 4 * int(std::ceil(config.quadDecimate));
    impl_->forgetHistory();
}

void TagTracker::Impl::makeDetectors()
{
    if (detector)
        return;
    std::set<int> ids;
    if (!(sizes.fallback > 0.0)) {
        for (const auto& [id, size] : sizes.byId)
            ids.insert(id);
        for (const TagMap& map : maps)
            for (const TagMapTag& tag : map.tags)
                ids.insert(tag.id);
    }
    sceneIds.assign(ids.begin(), ids.end());
    families = std::make_unique<SceneFamilies>(config.family, ids, config.maxBitErrors);
    detector = createDetector(config, *families, kLibraryThreadsAreSafe ? config.threads : 1, config.quadDecimate);
    const apriltag_detector_t& td = *detector;
    if (td.nthreads != config.threads) {
        LUMAR_LOG(Tracking, Info) << "libapriltag " << LUMAR_APRILTAG_VERSION
                                  << " can crash with several threads (fixed in 3.4.3): full frames on 1 thread, not "
                                  << config.threads;
    }
    // Not where the library writes into the frame: windows are disjoint, but one blurred in
    // place by one thread next to one read by the other is not worth the doubt.
    if (config.threads >= 2 && config.roi && !copyInput) {
        second = createDetector(config, *families, 1, config.quadDecimate);
        helper = std::make_unique<HelperThread>();
    }
    if (config.roi && config.coarseEvery > 0) {
        coarse = createDetector(config, *families, 1, config.coarseDecimate);
        coarseEvery = config.coarseEvery;
    }
    LUMAR_LOG(Tracking, Info) << "AprilTag " << config.family << " (corrects " << families->sceneBitErrors() << " bits"
                              << (families->split() ? " for the scene's " + std::to_string(sceneIds.size()) +
                                                          " ids, none for the others"
                                                    : std::string())
                              << ", decode tables " << int(families->decodeTableBytes() / 1024.0)
                              << " KiB), quad_decimate " << config.quadDecimate << ", quad_sigma " << config.quadSigma
                              << ", refine_edges " << config.refineEdges << ", " << td.nthreads << " threads"
                              << (second ? ", windows on 2 detectors" : "")
                              << (coarse ? ", a coarse search every " + std::to_string(config.coarseEvery) +
                                               " frames at quad_decimate " + std::to_string(config.coarseDecimate)
                                         : std::string());
}

void TagTracker::Impl::dropDetectors()
{
    // The helper thread first (it may hold the second detector), the families last.
    helper.reset();
    coarse.reset();
    second.reset();
    detector.reset();
    families.reset();
}

bool TagTracker::Impl::sceneHeld() const
{
    // Both sorted; lastIds may repeat an id.
    return !sceneIds.empty() && std::includes(lastIds.begin(), lastIds.end(), sceneIds.begin(), sceneIds.end());
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
    // The maps' tags join the scene's ids: the families are made again at the next detect().
    impl_->dropDetectors();
}

std::vector<MapDetection> TagTracker::detectMaps(const std::vector<TagDetection>& detections) const
{
    if (impl_->mapsValid && sameDetections(detections, impl_->mapsInput))
        return impl_->mapsResult;
    return impl_->solveMaps(detections);
}

std::vector<MapDetection> TagTracker::Impl::solveMaps(const std::vector<TagDetection>& detections) const
{
    std::vector<MapDetection> result;
    for (size_t i = 0; i < maps.size(); ++i) {
        MapDetection map;
        if (solveMapPose(maps[i], detections, intrinsics, map)) {
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

const std::vector<SearchWindow>& TagTracker::searchedWindows() const
{
    return impl_->lastWindows;
}

const TagTracker::SearchCounts& TagTracker::searchCounts() const
{
    return impl_->counts;
}

void TagTracker::reset(const CameraIntrinsics& intrinsics)
{
    validateIntrinsics(intrinsics);
    impl_->intrinsics = intrinsics;
    impl_->forgetHistory();
}

void TagTracker::Impl::forgetHistory()
{
    followed = FollowedTags(intrinsics.width, intrinsics.height, roiAlignment);
    lastIds.clear();
    lastWindows.clear();
    framesSinceFullSearch = 0;
    framesSinceCoarse = 0;
    fullSearchesSkipped = 0;
    coarseSearchesSkipped = 0;
    mapsInput.clear();
    mapsResult.clear();
    mapsValid = false;
    lastPoses.clear();
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
    ++impl_->frameCount;
    impl_->lastWindows.clear();
    if (luma.width < kMinImageSide || luma.height < kMinImageSide)
        return result;
    impl_->makeDetectors();

    // The library takes a mutable buffer but only reads it, except in the case above.
    uint8_t* pixels = const_cast<uint8_t*>(luma.data.data());
    if (impl_->copyInput) {
        impl_->scratch.assign(luma.data.begin(), luma.data.end());
        pixels = impl_->scratch.data();
    }
    // Search the followed tags' windows while the last frame found something; fall back to
    // the full frame when a tag of the last frame went missing there, and search the full
    // frame regularly anyway so that new tags are found.
    bool searched = false;
    SearchCounts& counts = impl_->counts;
    ++counts.frames;
    // While every scene tag is held, only every kAllHeldSearchSlowdown-th scheduled search is
    // made; the schedules themselves keep their pace (a full-frame search skipped leaves the
    // coarse search's count alone, as one made would), so that once a tag goes missing the
    // searches fall on the frames they would have fallen on anyway.
    const bool held = impl_->sceneHeld();
    const auto skip = [held](int& skipped) {
        if (held && ++skipped < kAllHeldSearchSlowdown)
            return true;
        skipped = 0;
        return false;
    };
    bool windowsFirst = impl_->roi && !impl_->lastIds.empty();
    bool fullSkipped = false;
    if (windowsFirst && ++impl_->framesSinceFullSearch >= impl_->fullFrameEvery) {
        fullSkipped = windowsFirst = skip(impl_->fullSearchesSkipped);
        if (fullSkipped)
            impl_->framesSinceFullSearch = 0;
    }
    if (windowsFirst) {
        searched = impl_->searchWindows(pixels, luma.width, luma.height, result);
        if (searched && !fullSkipped && impl_->coarse && ++impl_->framesSinceCoarse >= impl_->coarseEvery) {
            impl_->framesSinceCoarse = 0;
            if (!skip(impl_->coarseSearchesSkipped)) {
                ++counts.coarseSearches;
                if (impl_->coarseFindsMore(pixels, luma.width, luma.height, result)) {
                    searched = false;
                    ++counts.coarseCatches;
                }
            }
        }
        ++(searched ? counts.windowSearches : counts.fallbacks);
    }
    if (!searched) {
        ++counts.fullSearches;
        result.clear();
        impl_->lastWindows.clear();
        impl_->framesSinceFullSearch = 0;
        impl_->detectIn(*impl_->detector, pixels, luma.width, {0, 0, luma.width, luma.height}, result);
        sortDetections(result);
    }
    impl_->solvePoses(result);
    if (impl_->roi)
        impl_->follow(result);
    return result;
}

bool TagTracker::Impl::searchWindows(uint8_t* pixels, int width, int height, std::vector<TagDetection>& out)
{
    std::vector<SearchWindow> windows = followed.windows(frameCount, sceneHeld());
    // A sliver at the image's edge is not searched: a tag missing there brings the full frame.
    std::erase_if(windows,
                  [](const SearchWindow& w) { return w.x1 - w.x0 < kMinImageSide || w.y1 - w.y0 < kMinImageSide; });
    if (second && windows.size() >= 2) {
        std::vector<std::vector<TagDetection>> found(windows.size());
        searchInParallel(pixels, width, windows, found);
        for (size_t i = 0; i < windows.size(); ++i) {
            if (!wellInside(found[i], windows[i], width, height))
                return false;
            out.insert(out.end(), found[i].begin(), found[i].end());
        }
    } else {
        std::vector<TagDetection> found;
        for (const SearchWindow& w : windows) {
            found.clear();
            detectIn(*detector, pixels, width, w, found);
            if (!wellInside(found, w, width, height))
                return false;
            out.insert(out.end(), found.begin(), found.end());
        }
    }
    sortDetections(out);
    lastWindows = std::move(windows);
    // Every tag of the last frame found again (both lists sorted by id)? A tag missing now is
    // searched for at once in the full frame; if that misses it too, only its window is
    // searched on the following frames.
    // Copies of one id count one by one.
    size_t j = 0;
    for (const int id : lastIds) {
        while (j < out.size() && out[j].id < id)
            ++j;
        if (j == out.size() || out[j].id != id)
            return false;
        ++j;
    }
    return true;
}

bool TagTracker::Impl::coarseFindsMore(uint8_t* pixels, int width, int height,
                                       const std::vector<TagDetection>& windowResult)
{
    std::vector<TagDetection> found;
    detectIn(*coarse, pixels, width, {0, 0, width, height}, found);
    const auto centre = [](const TagDetection& d) {
        return 0.25 * (d.corners[0] + d.corners[1] + d.corners[2] + d.corners[3]);
    };
    for (const TagDetection& c : found) {
        // The same tag when a window found its id within half the tag's diagonal.
        const double near = 0.5 * glm::length(c.corners[2] - c.corners[0]);
        const bool held = std::any_of(windowResult.begin(), windowResult.end(), [&](const TagDetection& w) {
            return w.id == c.id && glm::length(centre(w) - centre(c)) <= near;
        });
        if (!held)
            return true;
    }
    return false;
}

void TagTracker::Impl::follow(const std::vector<TagDetection>& detections)
{
    lastIds.clear();
    for (const TagDetection& d : detections)
        lastIds.push_back(d.id);
    followed.seen(detections, frameCount);
    mapsValid = false;
    if (maps.empty())
        return;
    // The maps' tags not seen now, where each map's pose puts them: searched for from the
    // next frame on like tags just lost.
    mapsResult = solveMaps(detections);
    mapsInput = detections;
    mapsValid = true;
    for (const MapDetection& found : mapsResult)
        for (const TagMapTag& tag : maps[size_t(found.index)].tags) {
            if (std::binary_search(lastIds.begin(), lastIds.end(), tag.id))
                continue;
            std::array<glm::dvec2, 4> corners;
            if (projectMapTag(tag, found.cameraFromMap, intrinsics, corners))
                followed.predicted(tag.id, corners, frameCount);
        }
}

void TagTracker::Impl::solvePoses(std::vector<TagDetection>& detections)
{
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

void TagTracker::Impl::searchInParallel(uint8_t* pixels, int stride, const std::vector<SearchWindow>& windows,
                                        std::vector<std::vector<TagDetection>>& found)
{
    // The windows shared out by area (the detector's time grows with it), largest first, each
    // to the detector with less so far. Each thread writes only its own windows' results.
    std::vector<size_t> order(windows.size());
    for (size_t i = 0; i < order.size(); ++i)
        order[i] = i;
    const auto area = [&windows](size_t i) {
        const SearchWindow& w = windows[i];
        return int64_t(w.x1 - w.x0) * int64_t(w.y1 - w.y0);
    };
    std::stable_sort(order.begin(), order.end(), [&](size_t a, size_t b) { return area(a) > area(b); });
    std::vector<size_t> ours, theirs;
    int64_t ourArea = 0, theirArea = 0;
    for (const size_t i : order) {
        if (ourArea <= theirArea) {
            ours.push_back(i);
            ourArea += area(i);
        } else {
            theirs.push_back(i);
            theirArea += area(i);
        }
    }
    const auto searchOn = [&](apriltag_detector_t& td, const std::vector<size_t>& share) {
        for (const size_t i : share)
            detectIn(td, pixels, stride, windows[i], found[i]);
    };
    helper->runAlongside([&] { searchOn(*second, theirs); }, [&] { searchOn(*detector, ours); });
}

void TagTracker::Impl::detectIn(apriltag_detector_t& td, uint8_t* pixels, int stride, const SearchWindow& w,
                                std::vector<TagDetection>& out) const
{
    const int x0 = w.x0, y0 = w.y0;
    image_u8_t image{w.x1 - w.x0, w.y1 - w.y0, stride, pixels + size_t(y0) * size_t(stride) + size_t(x0)};
    const DetectionsPtr detections(apriltag_detector_detect(&td, &image));
    if (!detections)
        throw RuntimeError("AprilTag detection failed");

    const int count = zarray_size(detections.get());
    out.reserve(out.size() + size_t(count));
    for (int i = 0; i < count; ++i) {
        apriltag_detection_t* det = nullptr;
        zarray_get(detections.get(), i, &det);
        TagDetection d;
        d.id = families->idOf(*det);
        d.hamming = det->hamming;
        d.decisionMargin = det->decision_margin;
        // The library's pixel (0,0) covers [0,1]^2, ours [-0.5,0.5]^2 (DESIGN.md §5).
        for (int c = 0; c < 4; ++c)
            d.corners[size_t(c)] = {det->p[c][0] - 0.5 + x0, det->p[c][1] - 0.5 + y0};
        out.push_back(d);
    }
}

} // namespace lumar
