// TrackedPoses (issue 19): the filtered poses the renderer draws with, per tag and per map,
// held for kMarkerHoldFrames after the last measurement; and the helper thread the parallel
// window search runs on.
#include <atomic>
#include <cmath>
#include <stdexcept>

#include <gtest/gtest.h>

#include "core/helper_thread.h"
#include "tracking/tracked_poses.h"

namespace lumar {
namespace {

constexpr int64_t kFrameNs = 33'333'333;

TagDetection posedTag(int id, double x)
{
    TagDetection d;
    d.id = id;
    d.hasPose = true;
    d.cameraFromMarker.t = {x, 0.0, 1.0};
    return d;
}

TEST(TrackedPoses, TagsAndMapsUnderTheirKeysHeldForAFewFrames)
{
    TrackedPoses poses{TrackingConfig{}};
    MapDetection map;
    map.index = 1;
    map.cameraFromMap.t = {0.0, 0.2, 0.8};
    TagDetection unposed;
    unposed.id = 9;
    poses.update({posedTag(3, 0.1), unposed}, {map}, 10, 10 * kFrameNs);
    const auto tag = poses.poseAt(3, 10, 10 * kFrameNs);
    ASSERT_TRUE(tag);
    EXPECT_EQ(tag->lastSeen, 10u);
    EXPECT_EQ(tag->cameraFromMarker.t, glm::dvec3(0.1, 0.0, 1.0)) << "the first measurement passes unfiltered";
    EXPECT_FALSE(poses.poseAt(9, 10, 10 * kFrameNs)) << "a tag without a pose is not tracked";
    const auto board = poses.poseAt(TrackedPoses::mapKey(1), 10, 10 * kFrameNs);
    ASSERT_TRUE(board);
    EXPECT_EQ(board->cameraFromMarker.t, glm::dvec3(0.0, 0.2, 0.8));
    EXPECT_TRUE(TrackedPoses::isMapKey(board->key));
    EXPECT_EQ(TrackedPoses::mapIndex(board->key), 1);
    EXPECT_EQ(poses.all(10, 10 * kFrameNs).size(), 2u);
    EXPECT_TRUE(poses.poseAt(3, 10 + kMarkerHoldFrames, 10 * kFrameNs));
    EXPECT_FALSE(poses.poseAt(3, 11 + kMarkerHoldFrames, 10 * kFrameNs));
    EXPECT_TRUE(poses.all(11 + kMarkerHoldFrames, 10 * kFrameNs).empty());
}

TEST(TrackedPoses, FilteredWhenAskedAndRawOtherwise)
{
    TrackingConfig unfiltered;
    unfiltered.filter = false;
    TrackedPoses filtered{TrackingConfig{}}, raw{unfiltered};
    double filteredStep = 0.0, rawStep = 0.0, filteredLast = 0.0, rawLast = 0.0;
    for (int f = 0; f < 10; ++f) {
        const double x = f % 2 ? 0.001 : -0.001; // 1 mm of jitter about a still tag
        filtered.update({posedTag(0, x)}, {}, uint64_t(f), f * kFrameNs);
        raw.update({posedTag(0, x)}, {}, uint64_t(f), f * kFrameNs);
        const double filteredNow = filtered.poseAt(0, uint64_t(f), f * kFrameNs)->cameraFromMarker.t.x;
        const double rawNow = raw.poseAt(0, uint64_t(f), f * kFrameNs)->cameraFromMarker.t.x;
        filteredStep = std::abs(filteredNow - filteredLast);
        rawStep = std::abs(rawNow - rawLast);
        filteredLast = filteredNow;
        rawLast = rawNow;
    }
    EXPECT_EQ(raw.poseAt(0, 9, 9 * kFrameNs)->cameraFromMarker.t.x, 0.001) << "unfiltered: as measured";
    EXPECT_DOUBLE_EQ(rawStep, 0.002);
    EXPECT_LT(filteredStep, 0.5 * rawStep) << "filtered: the jitter smoothed";
}

TEST(HelperThread, RunsBothJobsAndRethrows)
{
    HelperThread helper;
    for (int i = 0; i < 100; ++i) {
        std::atomic<int> count{0};
        helper.runAlongside([&] { ++count; }, [&] { ++count; });
        EXPECT_EQ(count, 2);
    }
    EXPECT_THROW(helper.runAlongside([] { throw std::runtime_error("theirs"); }, [] {}), std::runtime_error);
    EXPECT_THROW(helper.runAlongside([] {}, [] { throw std::logic_error("ours"); }), std::logic_error);
    int after = 0;
    helper.runAlongside([&] { after += 1; }, [] {});
    EXPECT_EQ(after, 1) << "still works after an exception";
}

} // namespace
} // namespace lumar
