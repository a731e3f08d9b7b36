// The prefetching decorator must hand out exactly what the source produced, in order,
// including errors at the frame they happened, and shut down cleanly at any point.
#include <chrono>
#include <future>
#include <optional>
#include <thread>

#include <gtest/gtest.h>

#include "capture/fake_camera.h"
#include "capture/prefetching_source.h"
#include "core/error.h"

namespace lumar {
namespace {

// A scripted source: frames 0..count-1, an InputError instead of frame `failAt`. `ended`,
// when given, is set when the source reports its end.
class ScriptedSource final : public CaptureSource {
public:
    ScriptedSource(int count, int failAt, std::promise<void>* ended = nullptr)
        : count_(count), failAt_(failAt), ended_(ended)
    {
    }
    bool next(Frame& frame) override
    {
        if (produced_ >= count_) {
            if (ended_)
                std::exchange(ended_, nullptr)->set_value();
            return false;
        }
        const int k = produced_++;
        if (k == failAt_)
            throw InputError("clip.y4m: frame " + std::to_string(k) + " is truncated");
        frame.sequence = uint64_t(k);
        frame.rgb.reshape(4, 2, 3);
        std::fill(frame.rgb.data.begin(), frame.rgb.data.end(), uint8_t(k));
        return true;
    }
    int width() const override { return 4; }
    int height() const override { return 2; }
    double fps() const override { return 10.0; }

private:
    int count_, failAt_, produced_ = 0;
    std::promise<void>* ended_;
};

PrefetchOptions latestOnly()
{
    PrefetchOptions options;
    options.mode = PrefetchMode::LatestOnly;
    return options;
}

TEST(PrefetchingSource, FramesAndErrorsKeepTheirOrder)
{
    PrefetchingSource source(std::make_unique<ScriptedSource>(5, 2));
    EXPECT_EQ(source.width(), 4);
    EXPECT_EQ(source.fps(), 10.0);
    Frame f;
    ASSERT_TRUE(source.next(f));
    EXPECT_EQ(f.sequence, 0u);
    ASSERT_TRUE(source.next(f));
    EXPECT_EQ(f.sequence, 1u);
    EXPECT_EQ(f.rgb.data[0], 1);
    EXPECT_THROW(source.next(f), InputError);
    ASSERT_TRUE(source.next(f)) << "the stream goes on after a bad frame";
    EXPECT_EQ(f.sequence, 3u);
    ASSERT_TRUE(source.next(f));
    EXPECT_EQ(f.sequence, 4u);
    EXPECT_EQ(f.rgb.data[7], 4);
    EXPECT_FALSE(source.next(f));
    EXPECT_FALSE(source.next(f)) << "the end stays the end";
}

TEST(PrefetchingSource, SameBytesAsTheFakeCameraItself)
{
    CameraConfig config;
    config.width = 320;
    config.height = 240;
    FakeCamera direct(config);
    PrefetchingSource prefetched(std::make_unique<FakeCamera>(config));
    Frame a, b;
    for (int k = 0; k < 4; ++k) {
        ASSERT_TRUE(direct.next(a));
        ASSERT_TRUE(prefetched.next(b));
        EXPECT_EQ(a.sequence, b.sequence);
        EXPECT_EQ(a.timestampNs, b.timestampNs);
        EXPECT_EQ(a.rgb.data, b.rgb.data);
        EXPECT_EQ(a.luma.data, b.luma.data);
        EXPECT_GT(b.capturedNs, 0) << "a frame without a camera clock is stamped when made";
    }
}

TEST(PrefetchingSource, DestroyedWhileTheWorkerWaits)
{
    // The worker has a frame ready and waits for the consumer, who never comes.
    auto source = std::make_unique<PrefetchingSource>(std::make_unique<ScriptedSource>(100, -1));
    Frame f;
    ASSERT_TRUE(source->next(f));
    source.reset(); // must join without deadlock
    SUCCEED();
}

TEST(PrefetchingSource, InOrderDropsNothing)
{
    PrefetchingSource source(std::make_unique<ScriptedSource>(6, -1));
    EXPECT_EQ(source.mode(), PrefetchMode::InOrder);
    Frame f;
    for (uint64_t k = 0; k < 6; ++k) {
        ASSERT_TRUE(source.next(f));
        EXPECT_EQ(f.sequence, k);
    }
    EXPECT_FALSE(source.next(f));
    EXPECT_EQ(source.framesDropped(), 0u);
}

TEST(PrefetchingSource, LatestOnlyASlowConsumerGetsTheNewestFrame)
{
    // The consumer asks only once the source has made all its frames: it gets the last one,
    // the stale ones were dropped and counted.
    std::promise<void> ended;
    std::future<void> sourceEnded = ended.get_future();
    PrefetchingSource source(std::make_unique<ScriptedSource>(5, -1, &ended), latestOnly());
    EXPECT_EQ(source.mode(), PrefetchMode::LatestOnly);
    sourceEnded.wait();
    Frame f;
    ASSERT_TRUE(source.next(f));
    EXPECT_EQ(f.sequence, 4u);
    EXPECT_EQ(f.rgb.data[0], 4) << "the newest frame's own pixels, not a dropped one's";
    EXPECT_EQ(source.framesDropped(), 4u);
    EXPECT_FALSE(source.next(f));
    EXPECT_FALSE(source.next(f)) << "the end stays the end";
}

TEST(PrefetchingSource, LatestOnlyKeepsErrorsAndTheOrderOfWhatItHandsOver)
{
    // Whatever the threads' timing, frames come newer each time, the error comes once and
    // after every frame made before it, and every frame is either handed over or counted.
    for (int run = 0; run < 20; ++run) {
        PrefetchingSource source(std::make_unique<ScriptedSource>(8, 3), latestOnly());
        Frame f;
        std::optional<uint64_t> last;
        int errors = 0, delivered = 0;
        for (;;) {
            try {
                if (!source.next(f))
                    break;
            } catch (const InputError&) {
                ++errors;
                EXPECT_TRUE(!last || *last < 3u);
                continue;
            }
            if (last) {
                EXPECT_GT(f.sequence, *last);
            }
            EXPECT_EQ(f.rgb.data[0], uint8_t(f.sequence));
            EXPECT_EQ(errors, f.sequence > 3 ? 1 : 0);
            last = f.sequence;
            ++delivered;
        }
        EXPECT_EQ(errors, 1);
        ASSERT_TRUE(last);
        EXPECT_EQ(*last, 7u) << "the last frame is never dropped";
        EXPECT_EQ(uint64_t(delivered) + source.framesDropped(), 7u);
    }
}

TEST(PrefetchingSource, JustInTimeHandsOverEveryFrameOfTheFakeCameraInOrder)
{
    // Started when the consumer is expected, the frames are still the fake camera's own, one
    // after another, none dropped; a consumer that takes its time changes only when they are
    // drawn.
    CameraConfig config;
    config.width = 160;
    config.height = 120;
    FakeCamera direct(config);
    const PrefetchOptions options = prefetchOptionsFor("fake", true);
    ASSERT_EQ(options.mode, PrefetchMode::JustInTime);
    PrefetchingSource source(std::make_unique<FakeCamera>(config), options);
    Frame a, b;
    for (int k = 0; k < 6; ++k) {
        ASSERT_TRUE(direct.next(a));
        ASSERT_TRUE(source.next(b));
        EXPECT_EQ(a.sequence, b.sequence);
        EXPECT_EQ(a.rgb.data, b.rgb.data);
        std::this_thread::sleep_for(std::chrono::milliseconds(5 * k)); // the consumer at work
    }
    EXPECT_EQ(source.framesDropped(), 0u);
}

TEST(PrefetchingSource, JustInTimeKeepsErrorsAndTheEnd)
{
    PrefetchOptions options;
    options.mode = PrefetchMode::JustInTime;
    PrefetchingSource source(std::make_unique<ScriptedSource>(4, 1), options);
    Frame f;
    ASSERT_TRUE(source.next(f));
    EXPECT_EQ(f.sequence, 0u);
    EXPECT_THROW(source.next(f), InputError);
    ASSERT_TRUE(source.next(f));
    EXPECT_EQ(f.sequence, 2u);
    ASSERT_TRUE(source.next(f));
    EXPECT_EQ(f.sequence, 3u);
    EXPECT_FALSE(source.next(f));
}

TEST(PrefetchingSource, TheModeFollowsTheSourceKindAndTheCommand)
{
    for (const bool realTime : {false, true}) {
        EXPECT_EQ(prefetchOptionsFor("v4l2", realTime).mode, PrefetchMode::LatestOnly);
        EXPECT_EQ(prefetchOptionsFor("libcamera", realTime).mode, PrefetchMode::LatestOnly);
        EXPECT_EQ(prefetchOptionsFor("y4m", realTime).mode, PrefetchMode::InOrder);
        EXPECT_EQ(prefetchOptionsFor("images", realTime).mode, PrefetchMode::InOrder);
    }
    EXPECT_EQ(prefetchOptionsFor("fake", false).mode, PrefetchMode::InOrder) << "lumar render, bench";
    EXPECT_EQ(prefetchOptionsFor("fake", true).mode, PrefetchMode::JustInTime) << "lumar run";
}

} // namespace
} // namespace lumar
