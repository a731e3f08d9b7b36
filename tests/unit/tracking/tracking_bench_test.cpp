// `lumar-bench-tracking` (bench/tracking_bench.h): a small run has every condition x
// detector row, lumar finds every tag of the clean condition with sub-pixel corners, the
// sequence's ground truth is what each condition promises, and the JSON parses. No timing is
// asserted (benchmarks are not tests, DESIGN.md §9).
#include <cmath>
#include <set>
#include <sstream>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "bench/tracking_bench.h"
#include "bench/tracking_bench_scene.h"
#include "bench/tracking_scoring.h"
#include "bench/tracking_sequences.h"
#include "core/error.h"

namespace lumar {
namespace {

constexpr int kWidth = 640, kHeight = 360, kFrames = 3;

class TrackingBenchTest : public ::testing::Test {
protected:
    static void SetUpTestSuite()
    {
        TrackingBenchOptions options;
        options.width = kWidth;
        options.height = kHeight;
        options.framesPerCondition = kFrames;
        report_ = new TrackingBenchReport(runTrackingBench(options));
    }
    static void TearDownTestSuite()
    {
        delete report_;
        report_ = nullptr;
    }
    static const TrackingBenchRow& row(const std::string& condition, const std::string& detector)
    {
        for (const TrackingBenchRow& r : report_->rows)
            if (r.condition == condition && r.detector == detector)
                return r;
        throw std::runtime_error("no row " + condition + " x " + detector);
    }
    static TrackingBenchReport* report_;
};

TrackingBenchReport* TrackingBenchTest::report_ = nullptr;

TEST_F(TrackingBenchTest, HasEveryConditionTimesDetectorRow)
{
    const auto& conditions = TrackingBenchScene::conditions();
    ASSERT_EQ(conditions.size(), 9u);
    ASSERT_GE(report_->detectors.size(), 2u);
    EXPECT_EQ(report_->detectors[0], "lumar");
    EXPECT_EQ(report_->detectors[1], "apriltag");
    ASSERT_EQ(report_->rows.size(), (conditions.size() + 1) * report_->detectors.size());
    for (const BenchCondition& c : conditions)
        for (const std::string& d : report_->detectors) {
            const TrackingBenchRow& r = row(c.name, d);
            EXPECT_EQ(r.frames, kFrames) << c.name << " " << d;
            EXPECT_GE(r.msPerFrame, 0.0);
        }
    for (const std::string& d : report_->detectors)
        EXPECT_EQ(row("overall", d).frames, kFrames * int(conditions.size()));
    EXPECT_TRUE(std::isfinite(report_->lumarOverAprilTagTime));
    EXPECT_GT(report_->lumarOverAprilTagTime, 0.0);
}

TEST_F(TrackingBenchTest, LumarFindsEveryCleanTagWithSubPixelCorners)
{
    const TrackingBenchRow& lumar = row("clean", "lumar");
    EXPECT_EQ(lumar.visibleTags, kFrames);
    EXPECT_EQ(lumar.recall, 1.0);
    EXPECT_EQ(lumar.falsePositives, 0);
    EXPECT_LT(lumar.cornerMeanPx, 1.0);
    EXPECT_LT(lumar.cornerP95Px, 1.0);
    EXPECT_LT(lumar.rotationMeanDeg, 5.0);
    EXPECT_LT(lumar.translationMeanPercent, 2.0);
    // The library itself, corrected by the same half pixel, sees the same corners.
    const TrackingBenchRow& april = row("clean", "apriltag");
    EXPECT_EQ(april.recall, 1.0);
    EXPECT_LT(april.cornerMeanPx, 1.0);
    // ArUco (where built) without corner refinement: within a pixel or so, in the same corner
    // order (a wrong order puts the corners a tag's side away).
    if (report_->detectors.size() > 2) {
        const TrackingBenchRow& aruco = row("clean", "opencv_aruco");
        EXPECT_EQ(aruco.recall, 1.0);
        EXPECT_LT(aruco.cornerMeanPx, 1.5);
        EXPECT_LT(aruco.rotationMeanDeg, 10.0);
    }
}

TEST_F(TrackingBenchTest, FramesWithoutTagsHaveNoRecall)
{
    for (const std::string& d : report_->detectors) {
        const TrackingBenchRow& r = row("no_tags", d);
        EXPECT_EQ(r.visibleTags, 0) << d;
        EXPECT_TRUE(std::isnan(r.recall)) << d;
        EXPECT_TRUE(std::isnan(r.cornerMeanPx)) << d;
    }
}

TEST_F(TrackingBenchTest, JsonParsesWithTheSameRows)
{
    const nlohmann::json j = nlohmann::json::parse(trackingBenchJson(*report_));
    EXPECT_EQ(j.at("width"), kWidth);
    EXPECT_EQ(j.at("frames_per_condition"), kFrames);
    ASSERT_EQ(j.at("rows").size(), report_->rows.size());
    for (size_t i = 0; i < report_->rows.size(); ++i) {
        const auto& r = j.at("rows")[i];
        EXPECT_EQ(r.at("condition"), report_->rows[i].condition);
        EXPECT_EQ(r.at("detector"), report_->rows[i].detector);
        EXPECT_EQ(r.at("found"), report_->rows[i].found);
        if (std::isfinite(report_->rows[i].recall))
            EXPECT_NEAR(r.at("recall").get<double>(), report_->rows[i].recall, 1e-5);
        else
            EXPECT_TRUE(r.at("recall").is_null());
    }
    EXPECT_TRUE(j.at("lumar_over_apriltag_time").is_number());
}

TEST_F(TrackingBenchTest, MarkdownHasOneLinePerRow)
{
    const std::string md = trackingBenchMarkdown(*report_);
    std::istringstream lines(md);
    std::string line;
    int tableRows = 0;
    while (std::getline(lines, line))
        if (line.rfind("| ", 0) == 0)
            ++tableRows;
    EXPECT_EQ(tableRows, int(report_->rows.size()) + 1); // plus the header
    EXPECT_NE(md.find("| clean | lumar |"), std::string::npos);
    EXPECT_NE(md.find("lumar / apriltag"), std::string::npos);
}

TEST(TrackingBenchScene, GroundTruthMatchesEachCondition)
{
    const TrackingBenchScene scene(kWidth, kHeight, 7);
    const auto& conditions = TrackingBenchScene::conditions();
    BenchFrame frame;
    for (size_t c = 0; c < conditions.size(); ++c) {
        SCOPED_TRACE(conditions[c].name);
        for (int f = 0; f < 4; ++f) {
            scene.render(c, f, 4, frame);
            ASSERT_EQ(frame.luma.width, kWidth);
            ASSERT_EQ(frame.tags.size(), conditions[c].tags.size());
            int visible = 0;
            for (const BenchTagTruth& t : frame.tags) {
                visible += t.visible ? 1 : 0;
                if (!t.visible)
                    continue;
                // The corners are the pose's projection: the side in pixels matches size / depth.
                const double side = glm::length(t.corners[1] - t.corners[0]);
                EXPECT_GT(side, 0.0);
                EXPECT_LT(side, 2.0 * scene.intrinsics().fx * t.size / (t.cameraFromMarker.t.z - t.size));
            }
            if (conditions[c].lookAway)
                EXPECT_EQ(visible, 0);
            else if (conditions[c].name == "several_tags")
                EXPECT_GE(visible, 4);
            else
                EXPECT_EQ(visible, int(conditions[c].tags.size()));
        }
    }
}

TEST(TrackingBenchScene, SteepConditionReachesSeventyFiveDegrees)
{
    const TrackingBenchScene scene(kWidth, kHeight, 1);
    const auto& conditions = TrackingBenchScene::conditions();
    size_t steep = 0;
    while (conditions[steep].name != "steep_75deg")
        ++steep;
    BenchFrame frame;
    double maxAngle = 0.0, minAngle = 90.0;
    constexpr int kSweep = 40;
    for (int f = 0; f < kSweep; ++f) {
        scene.render(steep, f, kSweep, frame);
        const BenchTagTruth& t = frame.tags.front();
        // Angle between the tag's normal and the direction to the camera.
        const glm::dvec3 normal = t.cameraFromMarker.R * glm::dvec3(0, 0, 1);
        const double angle = std::acos(glm::dot(normal, -glm::normalize(t.cameraFromMarker.t))) * 180.0 / 3.14159265;
        maxAngle = std::max(maxAngle, angle);
        minAngle = std::min(minAngle, angle);
    }
    EXPECT_GT(maxAngle, 70.0);
    EXPECT_LT(maxAngle, 80.0);
    EXPECT_GT(minAngle, 50.0);
}

TEST(TrackingBenchScene, IsDeterministicPerSeed)
{
    const TrackingBenchScene a(kWidth, kHeight, 3), b(kWidth, kHeight, 3), c(kWidth, kHeight, 4);
    BenchFrame fa, fb, fc;
    a.render(1, 2, 5, fa);
    b.render(1, 2, 5, fb);
    c.render(1, 2, 5, fc);
    EXPECT_EQ(fa.luma.data, fb.luma.data);
    EXPECT_NE(fa.luma.data, fc.luma.data);
}

TEST(TrackingBench, RejectsBadOptions)
{
    TrackingBenchOptions options;
    options.framesPerCondition = 0;
    EXPECT_THROW(runTrackingBench(options), InputError);
    EXPECT_THROW(TrackingBenchScene(32, 32, 1), InputError);
}

// The one matching rule of the stills and the sequences: each detection to the nearest free tag
// of its id within kMatchRadiusPx; repeated ids (the library's photos) each find their own.
TEST(TrackingScoring, MatchesRepeatedIdsToTheNearestFreeTag)
{
    const auto square = [](double x, double y) {
        return std::array<glm::dvec2, 4>{glm::dvec2(x, y), glm::dvec2(x + 20, y), glm::dvec2(x + 20, y + 20),
                                         glm::dvec2(x, y + 20)};
    };
    std::vector<BenchTagTruth> truths(3);
    truths[0].id = 0;
    truths[0].corners = square(0, 0);
    truths[1].id = 0;
    truths[1].corners = square(100, 0);
    truths[2].id = 5;
    truths[2].corners = square(200, 0);
    std::vector<TagDetection> found(5);
    found[0].id = 0;
    found[0].corners = square(102, 1); // the second tag
    found[1].id = 0;
    found[1].corners = square(1, 0); // the first
    found[2].id = 0;
    found[2].corners = square(0, 2); // the first again: a false positive
    found[3].id = 6;
    found[3].corners = square(200, 0); // a wrong id
    found[4].id = 5;
    found[4].corners = square(200 + kMatchRadiusPx + 1, 0); // too far
    const FrameMatch match = matchDetections(truths, found);
    EXPECT_EQ(match.detectionOf, (std::vector<int>{1, 0, -1}));
    EXPECT_EQ(match.falsePositives, 3);
}

TEST(TrackingScoring, MarkdownTableHasAHeaderRuleAndRows)
{
    MarkdownTable table({"name", "value"}, 1);
    table.add({"a", fixed(1.26, 1)});
    table.add({"b", fixed(std::nan(""), 1)});
    EXPECT_EQ(table.str(), "| name | value |\n|---|---:|\n| a | 1.3 |\n| b | – |\n");
}

TEST(TrackingSequences, LumarVariantsAreTrackingTablesOverTheDefaults)
{
    const LumarVariant plain = parseLumarVariant("plain");
    EXPECT_EQ(plain.name, "plain");
    EXPECT_EQ(plain.config.threads, 1); // as the library's defaults
    EXPECT_EQ(plain.config.fullFrameEvery, TrackingConfig{}.fullFrameEvery);
    const LumarVariant coarse = parseLumarVariant("coarse:coarse_every=2,max_bit_errors=1,threads=2");
    EXPECT_EQ(coarse.config.coarseEvery, 2);
    EXPECT_EQ(coarse.config.maxBitErrors, 1);
    EXPECT_EQ(coarse.config.threads, 2);
    EXPECT_THROW(parseLumarVariant(":threads=1"), InputError);
    EXPECT_THROW(parseLumarVariant("bad:max_bit_errors=3"), InputError);
    EXPECT_THROW(parseLumarVariant("bad:no_such_key=1"), InputError);
}

} // namespace
} // namespace lumar
