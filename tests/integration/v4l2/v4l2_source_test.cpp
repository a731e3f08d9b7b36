// The V4L2 backend against the user-space virtual camera (tests/vcam, preloaded by ctest):
// streaming, colorimetry, and the injected faults. Each test configures the device through
// LUMAR_VCAM_* variables before opening it (the device reads them at open()).
#include <cstdlib>
#include <string>

#include <gtest/gtest.h>
#include <linux/videodev2.h>
#include <sys/wait.h>
#include <unistd.h>

#include "capture/v4l2/v4l2_source.h"
#include "core/error.h"
#include "vcam/vcam_pattern.h"

namespace lumar {
namespace {

const char* devicePath()
{
    const char* path = std::getenv("LUMAR_VCAM_DEVICE");
    return path != nullptr ? path : "/dev/video0";
}

class V4l2SourceTest : public ::testing::Test {
protected:
    void SetUp() override
    {
        if (std::getenv("LD_PRELOAD") == nullptr ||
            std::string(std::getenv("LD_PRELOAD")).find("lumar_vcam") == std::string::npos) {
            GTEST_SKIP() << "run through ctest, which preloads liblumar_vcam.so";
        }
        for (const char* name : {"LUMAR_VCAM_FORMATS", "LUMAR_VCAM_YCBCR_ENC", "LUMAR_VCAM_QUANTIZATION",
                                 "LUMAR_VCAM_FAULT_UNPLUG_AT", "LUMAR_VCAM_FAULT_STALL_AT", "LUMAR_VCAM_FAULT_STALL_MS",
                                 "LUMAR_VCAM_FAULT_DROP_EVERY", "LUMAR_VCAM_FAULT_SHORT_EVERY"}) {
            unsetenv(name);
        }
    }

    static V4l2Options options(int width = 640, int height = 480)
    {
        V4l2Options o;
        o.device = devicePath();
        o.width = width;
        o.height = height;
        o.fps = 60.0;
        o.bufferCount = 8; // slack for a loaded test machine: zero drops must hold
        return o;
    }
};

// Largest |decoded − expected| over the bars' centres, and whether the moving block sits
// where the frame's sequence number puts it.
int worstBarError(const Frame& frame, bool grey)
{
    int worst = 0;
    const auto& bars = vcam::colourBars();
    for (size_t bar = 0; bar < bars.size(); ++bar) {
        const int x = int((2 * bar + 1) * size_t(frame.rgb.width) / 16);
        const uint8_t* pixel = frame.rgb.at(x, frame.rgb.height / 4);
        int expected[3] = {bars[bar].r, bars[bar].g, bars[bar].b};
        if (grey) {
            const int y = int((299 * bars[bar].r + 587 * bars[bar].g + 114 * bars[bar].b + 500) / 1000);
            expected[0] = expected[1] = expected[2] = y;
        }
        for (int c = 0; c < 3; ++c) {
            worst = std::max(worst, std::abs(int(pixel[c]) - expected[c]));
        }
    }
    return worst;
}

bool blockWhereSequenceSays(const Frame& frame)
{
    const int left = vcam::blockLeft(int64_t(frame.sequence), frame.luma.width);
    const int row = (vcam::blockBandTop(frame.luma.height) + frame.luma.height) / 2;
    const uint8_t* luma = frame.luma.row(row);
    const bool inside = luma[left + vcam::kBlockWidth / 2] > 240;
    const bool before = left < 2 || luma[left - 2] < 15;
    const bool after = left + vcam::kBlockWidth + 2 > frame.luma.width || luma[left + vcam::kBlockWidth + 1] < 15;
    return inside && before && after;
}

void streamAndCheck(V4l2Source& source, const char* formatName, bool grey)
{
    Frame frame;
    int64_t firstTimestamp = 0;
    int64_t previousTimestamp = 0;
    uint64_t previousSequence = 0;
    for (int i = 0; i < 60; ++i) {
        ASSERT_TRUE(source.next(frame));
        if (i == 0) {
            firstTimestamp = frame.timestampNs;
        }
        ASSERT_EQ(frame.rgb.width, 640);
        ASSERT_EQ(frame.rgb.height, 480);
        ASSERT_EQ(frame.rgb.channels, 3);
        ASSERT_EQ(frame.luma.channels, 1);
        if (i > 0) {
            EXPECT_GT(frame.timestampNs, previousTimestamp) << formatName << " frame " << i;
            EXPECT_GT(frame.sequence, previousSequence) << formatName << " frame " << i;
        }
        previousTimestamp = frame.timestampNs;
        previousSequence = frame.sequence;
        EXPECT_LE(worstBarError(frame, grey), 2) << formatName << " frame " << i;
        EXPECT_TRUE(blockWhereSequenceSays(frame)) << formatName << " frame " << i;
    }
    EXPECT_EQ(source.framesDropped(), 0u) << formatName;
    EXPECT_EQ(source.framesCorrupt(), 0u) << formatName;
    // Sequences 0..59 without a gap, and 60 frames at 60 fps span 59 periods of 16.67 ms
    // (±1 ms: the device stamps each frame with its due time, rounded to microseconds).
    EXPECT_EQ(frame.sequence, 59u);
    EXPECT_NEAR(double(frame.timestampNs - firstTimestamp) / 1e6, 59.0 * 1000.0 / 60.0, 1.0);
}

TEST_F(V4l2SourceTest, PrefersNv12AndNegotiatesRequestedSize)
{
    V4l2Source source(options(1280, 720));
    EXPECT_EQ(source.pixelFormat(), uint32_t(V4L2_PIX_FMT_NV12));
    EXPECT_EQ(source.width(), 1280);
    EXPECT_EQ(source.height(), 720);
    EXPECT_DOUBLE_EQ(source.fps(), 60.0);
    EXPECT_GE(source.bufferCount(), 4u);
}

TEST_F(V4l2SourceTest, ClosestSizeWhenTheRequestIsNotOffered)
{
    V4l2Source source(options(800, 600)); // offered: 640x480, 1280x720
    EXPECT_EQ(source.width(), 640);
    EXPECT_EQ(source.height(), 480);
}

TEST_F(V4l2SourceTest, StreamsSixtyFramesInEachFormat)
{
    struct Offer {
        const char* formats;
        uint32_t expected;
    };
    for (Offer offer :
         {Offer{"YUYV", V4L2_PIX_FMT_YUYV}, Offer{"GREY,NV12", V4L2_PIX_FMT_NV12}, Offer{"GREY", V4L2_PIX_FMT_GREY}}) {
        setenv("LUMAR_VCAM_FORMATS", offer.formats, 1);
        V4l2Source source(options());
        ASSERT_EQ(source.pixelFormat(), offer.expected) << offer.formats;
        streamAndCheck(source, offer.formats, offer.expected == V4L2_PIX_FMT_GREY);
    }
}

TEST_F(V4l2SourceTest, FollowsTheDriversColorimetry)
{
    for (const char* format : {"YUYV", "NV12"}) {
        for (const char* encoding : {"601", "709"}) {
            for (const char* range : {"limited", "full"}) {
                setenv("LUMAR_VCAM_FORMATS", format, 1);
                setenv("LUMAR_VCAM_YCBCR_ENC", encoding, 1);
                setenv("LUMAR_VCAM_QUANTIZATION", range, 1);
                V4l2Source source(options());
                EXPECT_EQ(source.colorimetry().matrix,
                          std::string(encoding) == "709" ? YCbCrMatrix::Bt709 : YCbCrMatrix::Bt601);
                EXPECT_EQ(source.colorimetry().fullRange, std::string(range) == "full");
                Frame frame;
                ASSERT_TRUE(source.next(frame));
                EXPECT_LE(worstBarError(frame, false), 2) << format << " " << encoding << " " << range;
            }
        }
    }
}

TEST_F(V4l2SourceTest, CountsDroppedFrames)
{
    setenv("LUMAR_VCAM_FAULT_DROP_EVERY", "7", 1);
    V4l2Source source(options());
    Frame frame;
    const int delivered = 40;
    for (int i = 0; i < delivered; ++i) {
        ASSERT_TRUE(source.next(frame));
        EXPECT_NE((frame.sequence + 1) % 7, 0u) << "a dropped sequence number was delivered";
    }
    // Independent count: sequence numbers s ≤ last with (s + 1) divisible by 7 were dropped.
    const uint64_t last = frame.sequence;
    EXPECT_EQ(source.framesDropped(), (last + 1) / 7);
    EXPECT_EQ(source.framesDropped(), last + 1 - uint64_t(delivered));
}

TEST_F(V4l2SourceTest, SkipsShortFrames)
{
    setenv("LUMAR_VCAM_FAULT_SHORT_EVERY", "5", 1);
    V4l2Source source(options());
    Frame frame;
    for (int i = 0; i < 20; ++i) {
        ASSERT_TRUE(source.next(frame));
        EXPECT_NE((frame.sequence + 1) % 5, 0u) << "a short frame was delivered";
        EXPECT_LE(worstBarError(frame, false), 2);
    }
    EXPECT_EQ(source.framesCorrupt(), (frame.sequence + 1) / 5);
    EXPECT_EQ(source.framesDropped(), 0u); // short frames are corrupt, not dropped
}

TEST_F(V4l2SourceTest, UnplugGivesARuntimeError)
{
    setenv("LUMAR_VCAM_FAULT_UNPLUG_AT", "10", 1);
    V4l2Source source(options());
    Frame frame;
    int delivered = 0;
    try {
        for (; delivered < 100; ++delivered) {
            source.next(frame);
        }
        FAIL() << "no error after " << delivered << " frames";
    } catch (const RuntimeError& error) {
        EXPECT_NE(std::string(error.what()).find("unplugged"), std::string::npos) << error.what();
        EXPECT_NE(std::string(error.what()).find(devicePath()), std::string::npos) << error.what();
    }
    EXPECT_EQ(delivered, 10);
    // The destructor's STREAMOFF meets ENODEV and must not throw.
}

TEST_F(V4l2SourceTest, StallLongerThanTheTimeoutGivesATimeoutError)
{
    setenv("LUMAR_VCAM_FAULT_STALL_AT", "5", 1);
    setenv("LUMAR_VCAM_FAULT_STALL_MS", "1500", 1);
    V4l2Options o = options();
    o.frameTimeoutMs = 300;
    V4l2Source source(o);
    Frame frame;
    for (int i = 0; i < 5; ++i) {
        ASSERT_TRUE(source.next(frame));
    }
    try {
        source.next(frame);
        FAIL() << "no timeout";
    } catch (const RuntimeError& error) {
        EXPECT_EQ(std::string(error.what()), std::string(devicePath()) + ": no frame for 0.3 s");
    }
}

TEST_F(V4l2SourceTest, StallShorterThanTheTimeoutIsAGapInTimestamps)
{
    setenv("LUMAR_VCAM_FAULT_STALL_AT", "3", 1);
    setenv("LUMAR_VCAM_FAULT_STALL_MS", "200", 1);
    V4l2Source source(options());
    Frame frame;
    int64_t previous = 0;
    for (int i = 0; i < 6; ++i) {
        ASSERT_TRUE(source.next(frame));
        if (i == 3) {
            // One period (16.7 ms) plus the 200 ms stall.
            EXPECT_NEAR(double(frame.timestampNs - previous) / 1e6, 216.7, 1.0);
        }
        previous = frame.timestampNs;
    }
    EXPECT_EQ(source.framesDropped(), 0u);
}

TEST_F(V4l2SourceTest, MissingDeviceIsARuntimeError)
{
    V4l2Options o = options();
    o.device = "/dev/lumar-no-such-video-device";
    EXPECT_THROW(V4l2Source source(o), RuntimeError);
}

TEST_F(V4l2SourceTest, V4l2CtlStreamsFromTheVirtualDevice)
{
    if (std::system("command -v v4l2-ctl > /dev/null 2>&1") != 0) {
        GTEST_SKIP() << "v4l2-ctl (package v4l-utils) is not installed";
    }
    const std::string command = std::string("v4l2-ctl -d ") + devicePath() +
                                " --set-fmt-video=width=640,height=480,pixelformat=YUYV"
                                " --stream-mmap --stream-count=30 > /dev/null 2>&1";
    const int status = std::system(command.c_str());
    ASSERT_TRUE(WIFEXITED(status));
    EXPECT_EQ(WEXITSTATUS(status), 0) << command;
}

} // namespace
} // namespace lumar
