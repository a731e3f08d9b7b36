// The detector's families split by the scene's ids (scene_families.h): the scene's tags keep
// their bit-error correction, other ids are still named when read without error, and the
// decode tables shrink from the whole family's 36.5 MB (tag36h11, 2 bits) to a few hundred
// KiB, measured as the process' resident memory while the tracker makes its detectors.
#include <cstdio>
#include <fstream>
#include <string>
#include <utility>
#include <vector>

#include <gtest/gtest.h>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "tracking/scene_families.h"
#include "tracking/tag_map.h"
#include "tracking/tag_tracker.h"
#include "tracking_test_support.h"

namespace lumar {
namespace {

constexpr int kWidth = 320, kHeight = 240;
constexpr int kCellPx = 10;

CameraIntrinsics camera()
{
    return test::pinholeCamera(kWidth, kHeight, 300.0);
}

// Tags `ids` side by side, 10 px per cell, the data cells at `flipped` (column, row inside
// the black border) of every tag inverted.
Image8 tagsWithWrongBits(const std::vector<int>& ids, const std::vector<std::pair<int, int>>& flipped)
{
    cv::Mat image(kHeight, kWidth, CV_8UC1, cv::Scalar(128));
    int x = 20;
    for (const int id : ids) {
        char name[64];
        std::snprintf(name, sizeof(name), "/apriltag/tag36h11/tag36_11_%05d.png", id);
        cv::Mat png = cv::imread(std::string(LUMAR_TEST_DATA_DIR) + name, cv::IMREAD_GRAYSCALE);
        EXPECT_EQ(png.cols, 10) << name;
        for (const auto& [cx, cy] : flipped)
            png.at<uint8_t>(cy, cx) = uint8_t(255 - png.at<uint8_t>(cy, cx));
        cv::Mat tile;
        cv::resize(png, tile, {}, kCellPx, kCellPx, cv::INTER_NEAREST);
        tile.copyTo(image(cv::Rect(x, 70, tile.cols, tile.rows)));
        x += tile.cols + 40;
    }
    return test::toImage8(image);
}

std::vector<int> idsOf(const std::vector<TagDetection>& detections)
{
    std::vector<int> ids;
    for (const TagDetection& d : detections)
        ids.push_back(d.id);
    return ids;
}

TrackingConfig plainConfig()
{
    TrackingConfig config;
    config.roi = false;
    config.threads = 1;
    config.maxBitErrors = 2;
    return config;
}

TagSizes sized(std::initializer_list<int> ids)
{
    TagSizes sizes;
    for (const int id : ids)
        sizes.byId[id] = 0.1;
    return sizes;
}

TEST(SceneFamilies, TheScenesTagsKeepTheirCorrectionAndOthersAreNamedWhenExact)
{
    TagTracker tracker(plainConfig(), camera(), sized({3}));
    // Tag 3 is the scene's, tag 5 is not: exact, both are found with their own ids.
    EXPECT_EQ(idsOf(tracker.detect(tagsWithWrongBits({3, 5}, {}))), (std::vector<int>{3, 5}));
    // Two wrong bits in each: the scene's tag is corrected, the other is not named.
    const auto detections = tracker.detect(tagsWithWrongBits({3, 5}, {{2, 3}, {6, 5}}));
    ASSERT_EQ(idsOf(detections), (std::vector<int>{3}));
    EXPECT_EQ(detections[0].hamming, 2);
}

TEST(SceneFamilies, AMapsTagsJoinTheScene)
{
    TagTracker tracker(plainConfig(), camera(), sized({3}));
    TagMap map;
    map.name = "board";
    map.tags.push_back({5, 0.1, {}});
    tracker.setMaps({map});
    EXPECT_EQ(idsOf(tracker.detect(tagsWithWrongBits({3, 5}, {{2, 3}}))), (std::vector<int>{3, 5}));
}

TEST(SceneFamilies, AFallbackSizeKeepsTheWholeFamilyCorrected)
{
    // `lumar detect --tag-size`: every tag is posed, so every id is the scene's.
    TagSizes sizes = sized({3});
    sizes.fallback = 0.1;
    TagTracker tracker(plainConfig(), camera(), sizes);
    EXPECT_EQ(idsOf(tracker.detect(tagsWithWrongBits({3, 5}, {{2, 3}, {6, 5}}))), (std::vector<int>{3, 5}));
}

TEST(SceneFamilies, TheDecodeTablesAreSmallForAScene)
{
    const SceneFamilies whole("tag36h11", {}, 2);
    const SceneFamilies scene("tag36h11", {0, 1, 2, 3}, 2);
    EXPECT_FALSE(whole.split());
    EXPECT_TRUE(scene.split());
    EXPECT_EQ(scene.sceneBitErrors(), 2);
    EXPECT_GT(whole.decodeTableBytes(), 34.0 * 1024 * 1024); // 36.5 MB
    EXPECT_LT(scene.decodeTableBytes(), 0.5 * 1024 * 1024);
    // The large families get their full correction for a scene's ids, which the whole
    // family's table cannot afford (correctableBitsFor).
    EXPECT_LT(SceneFamilies("tagStandard52h13", {}, 2).sceneBitErrors(), 2);
    EXPECT_EQ(SceneFamilies("tagStandard52h13", {0, 7}, 2).sceneBitErrors(), 2);
}

long residentKiB()
{
    std::ifstream status("/proc/self/status");
    std::string line;
    while (std::getline(status, line))
        if (line.rfind("VmRSS:", 0) == 0)
            return std::stol(line.substr(6));
    return -1;
}

// Resident memory grown while a tracker with `sizes` makes its detectors (at its first detect).
long growthKiB(const TagSizes& sizes)
{
    TagTracker tracker(plainConfig(), camera(), sizes);
    const Image8 blank = tagsWithWrongBits({}, {});
    const long before = residentKiB();
    (void)tracker.detect(blank);
    return residentKiB() - before;
}

TEST(SceneFamilies, ResidentMemoryFollowsTheTables)
{
    TagSizes every;
    every.fallback = 0.1;
    const long wholeKiB = growthKiB(every);
    const long sceneKiB = growthKiB(sized({0, 1, 2, 3}));
    // The library writes every slot of its table while building it.
    EXPECT_GT(wholeKiB, 30 * 1024);
    EXPECT_LT(sceneKiB, 4 * 1024);
}

} // namespace
} // namespace lumar
