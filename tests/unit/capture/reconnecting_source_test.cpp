// Reconnection: a failing device is dropped, reopened with growing delays, and sequence
// numbers continue across the gap.
#include <chrono>

#include <gtest/gtest.h>

#include "capture/reconnecting_source.h"

namespace lumar {
namespace {

// A device that delivers `framesPerLife` frames per opening, then fails as if unplugged.
class FlakyDevice final : public CaptureSource {
public:
    explicit FlakyDevice(int framesPerLife) : left_(framesPerLife) {}
    bool next(Frame& frame) override
    {
        if (left_-- <= 0)
            throw RuntimeError("/dev/video9: unplugged");
        frame.sequence = sequence_++;
        return true;
    }
    int width() const override { return 8; }
    int height() const override { return 6; }
    double fps() const override { return 30; }

private:
    int left_;
    uint64_t sequence_ = 0;
};

TEST(ReconnectingSource, ReopensWithBackoffAndKeepsSequencesMonotonic)
{
    int opens = 0;
    int failuresToCome = 0;
    auto opener = [&]() -> std::unique_ptr<CaptureSource> {
        ++opens;
        if (failuresToCome > 0) {
            --failuresToCome;
            throw RuntimeError("/dev/video9: cannot open: No such device");
        }
        return std::make_unique<FlakyDevice>(3);
    };
    ReconnectingSource source(opener, "/dev/video9", {std::chrono::milliseconds(20), std::chrono::milliseconds(50)});
    EXPECT_EQ(source.width(), 8);
    Frame f;
    for (uint64_t k = 0; k < 3; ++k) {
        ASSERT_TRUE(source.next(f));
        EXPECT_EQ(f.sequence, k);
    }
    failuresToCome = 2; // the device stays away for two attempts
    // The backoff runs from the unplug, inside the next call: timed from before it (timed
    // from after, a slow throw, as under ThreadSanitizer, ate into the 20 ms it measured).
    const auto start = std::chrono::steady_clock::now();
    EXPECT_THROW(source.next(f), CameraUnavailable); // unplugged
    EXPECT_THROW(source.next(f), CameraUnavailable); // first reopen fails (after 20 ms)
    EXPECT_THROW(source.next(f), CameraUnavailable); // second fails (after 40 ms more)
    ASSERT_TRUE(source.next(f));                     // third succeeds (after 50 ms more)
    const auto waited = std::chrono::steady_clock::now() - start;
    EXPECT_GE(waited, std::chrono::milliseconds(20 + 40 + 50));
    EXPECT_LT(waited, std::chrono::milliseconds(2000));
    EXPECT_EQ(f.sequence, 3u) << "sequence continues after the last delivered frame";
    ASSERT_TRUE(source.next(f));
    EXPECT_EQ(f.sequence, 4u);
    EXPECT_EQ(source.reconnections(), 1);
    EXPECT_EQ(opens, 4);
}

TEST(ReconnectingSource, ACameraMissingAtStartIsAnError)
{
    auto opener = []() -> std::unique_ptr<CaptureSource> { throw RuntimeError("/dev/video9: cannot open"); };
    EXPECT_THROW(ReconnectingSource(opener, "/dev/video9"), RuntimeError);
}

} // namespace
} // namespace lumar
