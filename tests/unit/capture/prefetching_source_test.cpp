// The prefetching decorator must hand out exactly what the source produced, in order,
// including errors at the frame they happened, and shut down cleanly at any point.
#include <gtest/gtest.h>

#include "capture/fake_camera.h"
#include "capture/prefetching_source.h"
#include "core/error.h"

namespace lumar {
namespace {

// A scripted source: frames 0..count-1, an InputError instead of frame `failAt`.
class ScriptedSource final : public CaptureSource {
public:
    ScriptedSource(int count, int failAt) : count_(count), failAt_(failAt) {}
    bool next(Frame& frame) override
    {
        if (produced_ >= count_)
            return false;
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
};

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

} // namespace
} // namespace lumar
