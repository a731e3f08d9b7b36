// Re-acquisition in the region-of-interest search (issue 19): generated sequences of tags
// facing the camera, some of them hidden for a few frames. A tag missed on one frame, or
// occluded for a while, must be found on the first frame it shows again, not only at the
// next scheduled full-frame search; so must a [[maps]] board's tag whose place the board's
// pose predicts.
#include <cmath>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "core/error.h"
#include "tracking/followed_tags.h"
#include "tracking/tag_map.h"
#include "tracking/tag_tracker.h"
#include "tracking_test_support.h"

namespace lumar {
namespace {

constexpr int kWidth = 640, kHeight = 480;
constexpr int kCellPx = 10; // the PNG's 10x10 cells, 8 of them the black-bordered tag
constexpr int kFullFrameEvery = 10;

// A pinhole camera in which a 8 cm tag 0.5 m away, facing it, is 80 px wide: 10 px per cell.
CameraIntrinsics camera()
{
    return test::pinholeCamera(kWidth, kHeight, 500.0);
}

struct PlacedTag {
    int id = 0;
    int x = 0, y = 0; // top-left pixel of the tag's image (white ring included)
};

cv::Mat tagImage(int id)
{
    const std::string name =
        std::string(LUMAR_TEST_DATA_DIR) + "/apriltag/tag36h11/tag36_11_0000" + std::to_string(id) + ".png";
    const cv::Mat png = cv::imread(name, cv::IMREAD_GRAYSCALE);
    EXPECT_EQ(png.cols, 10) << name;
    cv::Mat scaled;
    cv::resize(png, scaled, {}, kCellPx, kCellPx, cv::INTER_NEAREST);
    return scaled;
}

// The tags drawn upright on a grey background: an exact image of tags facing the camera.
Image8 drawTags(const std::vector<PlacedTag>& tags)
{
    cv::Mat image(kHeight, kWidth, CV_8UC1, cv::Scalar(128));
    for (const PlacedTag& tag : tags) {
        const cv::Mat tile = tagImage(tag.id);
        tile.copyTo(image(cv::Rect(tag.x, tag.y, tile.cols, tile.rows)));
    }
    return test::toImage8(image);
}

TrackingConfig roiConfig()
{
    TrackingConfig config;
    config.roi = true;
    config.fullFrameEvery = kFullFrameEvery;
    config.threads = 1;
    return config;
}

bool found(const std::vector<TagDetection>& detections, int id)
{
    for (const TagDetection& d : detections)
        if (d.id == id)
            return true;
    return false;
}

// Two tags moving 2 px per frame to the right; tag 0 is hidden on the frames in [from, to).
std::vector<PlacedTag> twoTags(int frame, int hiddenFrom, int hiddenTo)
{
    std::vector<PlacedTag> tags{{1, 380 + 2 * frame, 220}};
    if (frame < hiddenFrom || frame >= hiddenTo)
        tags.push_back({0, 60 + 2 * frame, 120});
    return tags;
}

// A tag hidden on exactly one frame (every phase of the full-frame schedule) while the other
// stays in view is found again on the next frame.
TEST(Reacquisition, TagMissedOnOneFrameIsFoundOnTheNext)
{
    TagSizes sizes;
    sizes.fallback = 0.08;
    TagTracker tracker(roiConfig(), camera(), sizes);
    for (int hidden = 1; hidden <= kFullFrameEvery + 2; ++hidden) {
        SCOPED_TRACE("hidden on frame " + std::to_string(hidden));
        tracker.reset(camera()); // a new sequence, without building the detector again
        for (int frame = 0; frame <= hidden + 1; ++frame) {
            const auto detections = tracker.detect(drawTags(twoTags(frame, hidden, hidden + 1)));
            ASSERT_TRUE(found(detections, 1)) << "frame " << frame;
            EXPECT_EQ(found(detections, 0), frame != hidden) << "frame " << frame;
        }
    }
}

// Tag 0 hidden from frame `start` for 1 to 2 full_frame_every + 1 frames, tag 1 always in
// view: tag 0 is found on the first frame it shows again (the tracker reset before each).
void expectOcclusionsEndReacquiredAtOnce(TagTracker& tracker, int start)
{
    for (int length = 1; length <= 2 * kFullFrameEvery + 1; ++length) {
        SCOPED_TRACE("occluded for " + std::to_string(length) + " frames");
        tracker.reset(camera());
        for (int frame = 0; frame <= start + length; ++frame) {
            const auto detections = tracker.detect(drawTags(twoTags(frame, start, start + length)));
            ASSERT_TRUE(found(detections, 1)) << "frame " << frame;
            EXPECT_EQ(found(detections, 0), frame < start || frame >= start + length) << "frame " << frame;
        }
    }
}

// An occlusion of every length from 1 to 2 * full_frame_every + 1 frames, so that its end
// falls k frames after a full-frame search for every k in 1..full_frame_every-1 (the search
// made when the tag went missing, and the scheduled ones after it): the tag is found on the
// first frame it shows again.
TEST(Reacquisition, OcclusionEndingAtAnyFrameIsReacquiredAtOnce)
{
    TagSizes sizes;
    sizes.fallback = 0.08;
    TagTracker tracker(roiConfig(), camera(), sizes);
    expectOcclusionsEndReacquiredAtOnce(tracker, 3);
}

// coarse_every = 1: a tag entering the view while another one is followed is found on the first
// frame it shows, at every phase of the full-frame schedule, by the coarse search of the whole
// frame; without it, only at the next scheduled full-frame search.
TEST(Reacquisition, CoarseSearchFindsATagEnteringTheViewAtOnce)
{
    TagSizes sizes;
    sizes.fallback = 0.08;
    TrackingConfig coarse = roiConfig(), none = roiConfig();
    coarse.coarseEvery = 1;
    none.coarseEvery = 0;
    TagTracker withCoarse(coarse, camera(), sizes), without(none, camera(), sizes);
    int lateWithout = 0;
    for (int appear = 1; appear <= kFullFrameEvery + 1; ++appear) {
        SCOPED_TRACE("tag 0 enters on frame " + std::to_string(appear));
        withCoarse.reset(camera());
        without.reset(camera());
        for (int frame = 0; frame <= appear; ++frame) {
            std::vector<PlacedTag> tags{{1, 380, 220}};
            if (frame >= appear)
                tags.push_back({0, 60, 120});
            const Image8 image = drawTags(tags);
            const auto a = withCoarse.detect(image), b = without.detect(image);
            ASSERT_TRUE(found(a, 1)) << "frame " << frame;
            EXPECT_EQ(found(a, 0), frame >= appear) << "frame " << frame;
            if (frame == appear && !found(b, 0))
                ++lateWithout;
        }
    }
    EXPECT_GT(lateWithout, 0); // what the coarse search is for
    EXPECT_GT(withCoarse.searchCounts().coarseCatches, 0u);
    EXPECT_GT(withCoarse.searchCounts().windowSearches, 0u); // the windows still stood on the other frames
}

// Two copies of one id: the one missed on a frame is found again on the next, the other
// still followed where it is.
TEST(Reacquisition, EachCopyOfARepeatedIdIsFollowed)
{
    TagSizes sizes;
    sizes.fallback = 0.08;
    TagTracker tracker(roiConfig(), camera(), sizes);
    for (int hidden = 0; hidden < 2; ++hidden) {
        SCOPED_TRACE("copy " + std::to_string(hidden) + " hidden");
        tracker.reset(camera());
        for (int frame = 0; frame < 5; ++frame) {
            std::vector<PlacedTag> tags{{1, 260, 300}};
            if (frame != 2 || hidden != 0)
                tags.push_back({0, 40, 60});
            if (frame != 2 || hidden != 1)
                tags.push_back({0, 480, 60});
            EXPECT_EQ(tracker.detect(drawTags(tags)).size(), tags.size()) << "frame " << frame;
        }
    }
}

// A 2x2 board of 8 cm tags 20 cm apart, 0.5 m in front of the camera and facing it.
MapConfig board()
{
    MapConfig map;
    map.name = "board";
    map.tags = {{0, 0.08, {-0.1, 0.1, 0.0}, {0.0, 0.0, 0.0}},
                {1, 0.08, {0.1, 0.1, 0.0}, {0.0, 0.0, 0.0}},
                {2, 0.08, {-0.1, -0.1, 0.0}, {0.0, 0.0, 0.0}},
                {3, 0.08, {0.1, -0.1, 0.0}, {0.0, 0.0, 0.0}}};
    return map;
}

// Where the camera above sees the board's tag at map (x, y): 1000 px per metre about the
// image's centre, the map's y up; the top-left of its 100 px image.
PlacedTag boardTag(int id, double x, double y)
{
    return {id, int(std::lround(270.0 + 1000.0 * x)), int(std::lround(190.0 - 1000.0 * y))};
}

// The board's lower tags are covered until frame `appear` (every phase of the schedule): the
// board's pose, solved from its upper tags, predicts them, and they are found on that frame.
TEST(Reacquisition, BoardTagsPredictedByTheBoardPoseAreFoundWhenTheyAppear)
{
    const MapConfig config = board();
    TagTracker tracker(roiConfig(), camera(), TagSizes{});
    tracker.setMaps({makeTagMap(config)});
    for (int appear = 2; appear <= kFullFrameEvery + 2; ++appear) {
        SCOPED_TRACE("lower tags appear on frame " + std::to_string(appear));
        tracker.reset(camera());
        for (int frame = 0; frame <= appear; ++frame) {
            std::vector<PlacedTag> tags{boardTag(0, -0.1, 0.1), boardTag(1, 0.1, 0.1)};
            if (frame >= appear) {
                tags.push_back(boardTag(2, -0.1, -0.1));
                tags.push_back(boardTag(3, 0.1, -0.1));
            }
            const auto detections = tracker.detect(drawTags(tags));
            ASSERT_EQ(detections.size(), tags.size()) << "frame " << frame;
            const auto maps = tracker.detectMaps(detections);
            ASSERT_EQ(maps.size(), 1u) << "frame " << frame;
            EXPECT_EQ(maps[0].tagsUsed, int(tags.size()));
            EXPECT_NEAR(maps[0].cameraFromMap.t.z, 0.5, 0.01);
        }
    }
}

// reset() forgets the sequence: the next image is searched whole, as by a new tracker.
TEST(Reacquisition, ResetSearchesTheNextImageAsAStill)
{
    TagSizes sizes;
    sizes.fallback = 0.08;
    TagTracker tracker(roiConfig(), camera(), sizes);
    ASSERT_EQ(tracker.detect(drawTags({{0, 60, 120}})).size(), 1u);
    tracker.reset(camera());
    // Far from the last tag's window, but found at once.
    const auto detections = tracker.detect(drawTags({{1, 500, 350}}));
    ASSERT_EQ(detections.size(), 1u);
    EXPECT_EQ(detections[0].id, 1);
    EXPECT_THROW(tracker.reset(CameraIntrinsics{}), InputError);
}

// threads = 2 (issue 19): the followed tags' windows are searched on two detectors at once;
// every window is searched as one detector searches it, so the results are the same, frame
// by frame, through misses, occlusions and re-acquisitions.
TEST(Reacquisition, TwoDetectorsFindExactlyWhatOneFinds)
{
    TagSizes sizes;
    sizes.fallback = 0.08;
    TrackingConfig two = roiConfig();
    two.threads = 2;
    TagTracker one(roiConfig(), camera(), sizes), parallel(two, camera(), sizes);
    for (int frame = 0; frame < 3 * kFullFrameEvery; ++frame) {
        // Three tags far apart (three windows), one of them hidden now and then.
        std::vector<PlacedTag> tags = twoTags(frame, 5, 8);
        if (frame % 7 != 3)
            tags.push_back({2, 200 + frame, 340});
        const Image8 image = drawTags(tags);
        const auto a = one.detect(image), b = parallel.detect(image);
        ASSERT_EQ(a.size(), b.size()) << "frame " << frame;
        for (size_t i = 0; i < a.size(); ++i) {
            EXPECT_EQ(a[i].id, b[i].id) << "frame " << frame;
            EXPECT_EQ(a[i].corners, b[i].corners) << "frame " << frame;
            EXPECT_EQ(a[i].hasPose, b[i].hasPose) << "frame " << frame;
        }
        EXPECT_EQ(found(b, 0), frame < 5 || frame >= 8) << "frame " << frame;
        EXPECT_EQ(found(b, 2), frame % 7 != 3) << "frame " << frame;
    }
    EXPECT_EQ(parallel.searchCounts().windowSearches, one.searchCounts().windowSearches);
    EXPECT_GT(parallel.searchCounts().windowSearches, 0u);
}

// The windows a frame was searched in (what the setup view draws): none on a full-frame
// search, otherwise windows that hold every tag found, and none at all with roi off.
TEST(Reacquisition, SearchedWindowsHoldTheTagsFoundInThem)
{
    TagSizes sizes;
    sizes.fallback = 0.08;
    TagTracker tracker(roiConfig(), camera(), sizes);
    int framesWithWindows = 0;
    for (int frame = 0; frame <= kFullFrameEvery; ++frame) {
        SCOPED_TRACE("frame " + std::to_string(frame));
        const std::vector<TagDetection> detections = tracker.detect(drawTags(twoTags(frame, 0, 0)));
        ASSERT_EQ(detections.size(), 2u);
        const std::vector<SearchWindow>& windows = tracker.searchedWindows();
        if (frame == 0 || frame == kFullFrameEvery) {
            EXPECT_TRUE(windows.empty()); // the first and the scheduled full-frame search
        }
        if (windows.empty())
            continue;
        ++framesWithWindows;
        for (const SearchWindow& w : windows)
            EXPECT_TRUE(w.x0 >= 0 && w.y0 >= 0 && w.x1 <= kWidth && w.y1 <= kHeight && w.x0 < w.x1 && w.y0 < w.y1);
        for (const TagDetection& d : detections) {
            bool inside = false;
            for (const SearchWindow& w : windows) {
                bool all = true;
                for (const glm::dvec2& c : d.corners)
                    all = all && c.x >= w.x0 && c.x < w.x1 && c.y >= w.y0 && c.y < w.y1;
                inside = inside || all;
            }
            EXPECT_TRUE(inside) << "tag " << d.id;
        }
    }
    // Windows are reported exactly for the frames whose window search stood.
    EXPECT_EQ(uint64_t(framesWithWindows), tracker.searchCounts().windowSearches);
    EXPECT_GT(framesWithWindows, 0);
    TrackingConfig whole = roiConfig();
    whole.roi = false;
    TagTracker fullFrames(whole, camera(), sizes);
    for (int frame = 0; frame < 3; ++frame) {
        EXPECT_EQ(fullFrames.detect(drawTags(twoTags(frame, 0, 0))).size(), 2u);
        EXPECT_TRUE(fullFrames.searchedWindows().empty());
    }
}

// Tags 0 and 1 with sizes and no default size: the scene's tags.
TagSizes sceneSizes()
{
    TagSizes sizes;
    sizes.byId = {{0, 0.08}, {1, 0.08}};
    return sizes;
}

// Two trackers with a coarse search every 3 frames: `held` knows only the scene's tags (so
// it slows its searches for new tags while it holds them all), `paced` poses any tag (a
// default size), so its searches keep their pace.
struct HeldAndPaced {
    static TagSizes anyTag()
    {
        TagSizes sizes;
        sizes.fallback = 0.08;
        return sizes;
    }
    static TrackingConfig config()
    {
        TrackingConfig c = roiConfig();
        c.coarseEvery = 3;
        return c;
    }
    TagTracker held{config(), camera(), sceneSizes()};
    TagTracker paced{config(), camera(), anyTag()};
};

// While every scene tag is found frame after frame, the searches for new tags (the full-frame
// one every full_frame_every frames, the coarse one every coarse_every) run six times less
// often; with a default size any tag in view may be posed, so they keep their pace.
TEST(Reacquisition, SearchesForNewTagsSlowDownWhileEverySceneTagIsHeld)
{
    HeldAndPaced trackers;
    TagTracker& held = trackers.held;
    TagTracker& paced = trackers.paced;
    constexpr int kFrames = 6 * kFullFrameEvery;
    for (int frame = 0; frame < kFrames; ++frame) {
        const Image8 image = drawTags(twoTags(frame, 0, 0));
        ASSERT_EQ(held.detect(image).size(), 2u) << "frame " << frame;
        ASSERT_EQ(paced.detect(image).size(), 2u) << "frame " << frame;
    }
    EXPECT_GE(paced.searchCounts().fullSearches, uint64_t(kFrames / kFullFrameEvery));
    EXPECT_GE(paced.searchCounts().coarseSearches, uint64_t(kFrames / 3 - kFrames / kFullFrameEvery));
    EXPECT_EQ(held.searchCounts().fullSearches, 1u); // the first frame's
    EXPECT_LE(held.searchCounts().coarseSearches, uint64_t(kFrames / 18));
    EXPECT_GT(held.searchCounts().coarseSearches, 0u);
    EXPECT_EQ(held.searchCounts().fallbacks, 0u);
}

// Once a scene tag goes missing, the full-frame and coarse searches fall on the frames they
// fall on for a tracker that never slowed them (one with a default size): the slowed
// schedules keep their phase, so re-acquisition is as quick as without the slowdown.
TEST(Reacquisition, SchedulesKeepTheirPhaseThroughTheSlowdown)
{
    HeldAndPaced trackers;
    TagTracker& held = trackers.held;
    TagTracker& paced = trackers.paced;
    constexpr int kGone = 3 * kFullFrameEvery - 3; // tag 0 leaves after 27 frames held
    for (int frame = 0; frame < kGone + 3 * kFullFrameEvery; ++frame) {
        const uint64_t heldCoarse = held.searchCounts().coarseSearches;
        const uint64_t pacedCoarse = paced.searchCounts().coarseSearches;
        const Image8 image = drawTags(twoTags(frame, kGone, 1000));
        ASSERT_EQ(held.detect(image).size(), paced.detect(image).size()) << "frame " << frame;
        if (frame <= kGone)
            continue;
        EXPECT_EQ(held.searchedWindows().empty(), paced.searchedWindows().empty()) << "frame " << frame;
        EXPECT_EQ(held.searchCounts().coarseSearches - heldCoarse, paced.searchCounts().coarseSearches - pacedCoarse)
            << "frame " << frame;
    }
}

// Scene tags with sizes: one hidden on a single frame at every phase of the slow schedule is
// found on the next frame, and one occluded for up to 2 * full_frame_every + 1 frames on the
// first frame it shows again (while it is missing the searches keep their pace).
TEST(Reacquisition, SceneTagsMissedAtAnyPhaseOfTheSlowScheduleAreFoundAtOnce)
{
    TagTracker tracker(roiConfig(), camera(), sceneSizes());
    // Each phase of the first full-frame period, then those about the slowed coarse and
    // full-frame searches (every 18 and 60 frames).
    std::vector<int> phases;
    for (int hidden = 1; hidden <= kFullFrameEvery + 2; ++hidden)
        phases.push_back(hidden);
    for (int hidden : {17, 18, 19, 35, 36, 37, 53, 54, 55, 59, 60, 61, 62})
        phases.push_back(hidden);
    for (const int hidden : phases) {
        SCOPED_TRACE("hidden on frame " + std::to_string(hidden));
        tracker.reset(camera());
        for (int frame = 0; frame <= hidden + 1; ++frame) {
            const auto detections = tracker.detect(drawTags(twoTags(frame, hidden, hidden + 1)));
            ASSERT_TRUE(found(detections, 1)) << "frame " << frame;
            EXPECT_EQ(found(detections, 0), frame != hidden) << "frame " << frame;
        }
    }
    expectOcclusionsEndReacquiredAtOnce(tracker, 25);
}

// A square tag `side` px wide with its top-left corner at (x, y), in the AprilTag order.
TagDetection squareTag(double x, double y, double side)
{
    TagDetection d;
    d.id = 0;
    d.corners = {glm::dvec2(x, y + side), glm::dvec2(x + side, y + side), glm::dvec2(x + side, y), glm::dvec2(x, y)};
    return d;
}

// A window's margin: half the tag's size for a tag seen once (its motion unknown) or missed on
// the last frame, but with tight windows only kMinRoiMargin (48 px) past the most its corners
// moved per frame for a tag seen on the last two frames.
TEST(FollowedTagWindows, MarginFollowsTheTagsMotionOnceKnown)
{
    FollowedTags followed(1280, 720, 8);
    constexpr double kSide = 200.0;
    followed.seen({squareTag(500.0, 200.0, kSide)}, 1);
    std::vector<SearchWindow> windows = followed.windows(2, true);
    ASSERT_EQ(windows.size(), 1u);
    EXPECT_GE(windows[0].x1 - windows[0].x0, int(2.0 * kSide) - 8); // margin 100 px, origin aligned down
    followed.seen({squareTag(505.0, 200.0, kSide)}, 2);             // 5 px per frame to the right
    windows = followed.windows(3, false);
    ASSERT_EQ(windows.size(), 1u);
    EXPECT_GE(windows[0].x1, 710 + 100); // not tight: half the tag's size
    windows = followed.windows(3, true);
    ASSERT_EQ(windows.size(), 1u);
    const SearchWindow& w = windows[0];
    // Predicted at x 510..710: the window reaches 53 px past it (and down to a multiple of 8).
    EXPECT_LE(w.x0, 510 - 53);
    EXPECT_GE(w.x0, 510 - 53 - 8);
    EXPECT_EQ(w.x1, 710 + 53);
    EXPECT_LE(w.y0, 200 - 53);
    EXPECT_EQ(w.y1, 400 + 53);
    // Missed on frame 3: the full margin again, grown by half the motion per frame missed.
    windows = followed.windows(4, true);
    ASSERT_EQ(windows.size(), 1u);
    EXPECT_GE(windows[0].x1, 715 + 100);
    EXPECT_LE(windows[0].y0, 200 - 100);
}

} // namespace
} // namespace lumar
