// The replay source serves exactly the frames its source made, forwards and back, with the
// fake camera's ground truth, steadily counting timestamps and a capture time on the
// monotonic clock.
#include <gtest/gtest.h>

#include "capture/fake_camera.h"
#include "capture/replay_source.h"
#include "core/error.h"
#include "core/monotonic_clock.h"

namespace lumar {
namespace {

// Frames 0..count-1, each filled with its number.
class CountingSource final : public CaptureSource {
public:
    explicit CountingSource(int count) : count_(count) {}
    bool next(Frame& frame) override
    {
        if (produced_ >= count_)
            return false;
        frame.sequence = uint64_t(produced_);
        frame.rgb.reshape(4, 2, 3);
        frame.luma.reshape(4, 2, 1);
        std::fill(frame.rgb.data.begin(), frame.rgb.data.end(), uint8_t(produced_));
        std::fill(frame.luma.data.begin(), frame.luma.data.end(), uint8_t(100 + produced_));
        ++produced_;
        return true;
    }
    int width() const override { return 4; }
    int height() const override { return 2; }
    double fps() const override { return 25.0; }

private:
    int count_, produced_ = 0;
};

TEST(ReplaySource, LoopsForwardsAndBackWithSteadyTimestamps)
{
    ReplaySource replay(std::make_unique<CountingSource>(100), 4);
    EXPECT_EQ(replay.framesHeld(), 4);
    EXPECT_EQ(replay.width(), 4);
    EXPECT_EQ(replay.fps(), 25.0);
    EXPECT_EQ(replay.bytesHeld(), 4u * (24 + 8));
    const int expected[] = {0, 1, 2, 3, 2, 1, 0, 1, 2, 3, 2};
    Frame f;
    int64_t previousCaptured = 0;
    for (int k = 0; k < int(std::size(expected)); ++k) {
        const int64_t before = monotonicClockNs();
        ASSERT_TRUE(replay.next(f));
        EXPECT_EQ(replay.heldIndex(uint64_t(k)), expected[k]);
        EXPECT_EQ(f.rgb.data[0], expected[k]) << "frame " << k;
        EXPECT_EQ(f.luma.data[7], 100 + expected[k]) << "frame " << k;
        EXPECT_EQ(f.sequence, uint64_t(k));
        EXPECT_EQ(f.timestampNs, int64_t(k) * 40'000'000);
        EXPECT_GE(f.capturedNs, before) << "stamped when served";
        EXPECT_GE(f.capturedNs, previousCaptured);
        previousCaptured = f.capturedNs;
    }
    EXPECT_TRUE(replay.groundTruth(0).empty()) << "not a fake camera";
}

TEST(ReplaySource, AShortSourceGivesWhatItHasAndOneFrameRepeats)
{
    ReplaySource replay(std::make_unique<CountingSource>(1), 8);
    EXPECT_EQ(replay.framesHeld(), 1);
    Frame f;
    for (int k = 0; k < 3; ++k) {
        ASSERT_TRUE(replay.next(f));
        EXPECT_EQ(f.rgb.data[0], 0);
    }
}

TEST(ReplaySource, FramesAreLentNotCopied)
{
    ReplaySource replay(std::make_unique<CountingSource>(100), 3);
    Frame f;
    std::vector<const uint8_t*> served; // the rgb storage served as each held frame
    for (uint64_t k = 0; k < 9; ++k) {
        ASSERT_TRUE(replay.next(f));
        const size_t held = size_t(replay.heldIndex(k));
        if (served.size() <= held)
            served.resize(held + 1, nullptr);
        if (served[held] == nullptr)
            served[held] = f.rgb.data.data();
        EXPECT_EQ(f.rgb.data.data(), served[held]) << "frame " << k << " was copied";
        EXPECT_EQ(f.rgb.data[0], held) << "frame " << k;
    }
    EXPECT_EQ(replay.bytesHeld(), 3u * (24 + 8)) << "counted while one is lent";
}

TEST(ReplaySource, AFrameNotGivenBackIsARuntimeError)
{
    ReplaySource replay(std::make_unique<CountingSource>(100), 3);
    Frame first, other;
    ASSERT_TRUE(replay.next(first));
    EXPECT_THROW(replay.next(other), RuntimeError);
}

TEST(ReplaySource, NoFrameIsBadInput)
{
    EXPECT_THROW(ReplaySource(std::make_unique<CountingSource>(0), 4), InputError);
    EXPECT_THROW(ReplaySource(std::make_unique<CountingSource>(5), 0), InputError);
}

TEST(ReplaySource, FakeCameraFramesAndGroundTruthAsDrawn)
{
    CameraConfig config;
    config.width = 320;
    config.height = 180;
    const FakeCamera direct(config);
    ReplaySource replay(std::make_unique<FakeCamera>(config), 3);
    Frame served, drawn;
    for (uint64_t k = 0; k < 6; ++k) {
        ASSERT_TRUE(replay.next(served));
        const uint64_t held = uint64_t(replay.heldIndex(k));
        direct.render(held, drawn);
        EXPECT_EQ(served.rgb.data, drawn.rgb.data) << "frame " << k;
        EXPECT_EQ(served.luma.data, drawn.luma.data) << "frame " << k;
        const std::vector<TagGroundTruth> expected = direct.groundTruth(held);
        const std::vector<TagGroundTruth>& truth = replay.groundTruth(k);
        ASSERT_EQ(truth.size(), expected.size());
        for (size_t i = 0; i < truth.size(); ++i) {
            EXPECT_EQ(truth[i].id, expected[i].id);
            EXPECT_EQ(truth[i].cameraFromMarker.t, expected[i].cameraFromMarker.t);
        }
    }
}

} // namespace
} // namespace lumar
