// The V4L2 backend against the user-space virtual camera (tests/vcam, preloaded by ctest):
// streaming, colorimetry, MJPEG, controls, source changes and the injected faults. Each test
// configures the device through LUMAR_VCAM_* variables before opening it (the device reads
// them when its first handle opens).
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include <fcntl.h>
#include <gtest/gtest.h>
#include <linux/videodev2.h>
#include <sys/ioctl.h>
#include <sys/wait.h>
#include <unistd.h>

#include "capture/v4l2/v4l2_controls.h"
#include "capture/v4l2/v4l2_format.h"
#include "capture/v4l2/v4l2_ioctl.h"
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
        for (const char* name :
             {"LUMAR_VCAM_FORMATS", "LUMAR_VCAM_YCBCR_ENC", "LUMAR_VCAM_QUANTIZATION", "LUMAR_VCAM_FAULT_UNPLUG_AT",
              "LUMAR_VCAM_FAULT_STALL_AT", "LUMAR_VCAM_FAULT_STALL_MS", "LUMAR_VCAM_FAULT_DROP_EVERY",
              "LUMAR_VCAM_FAULT_SHORT_EVERY", "LUMAR_VCAM_FAULT_CORRUPT_EVERY", "LUMAR_VCAM_JPEG_QUALITY",
              "LUMAR_VCAM_SOURCE_CHANGE_AT", "LUMAR_VCAM_SOURCE_CHANGE_SIZE"}) {
            unsetenv(name);
        }
        // The device keeps pace with this process, not with the wall clock. These tests
        // count the drops, corrupt frames and faults the device injects at given frames; on
        // a loaded machine a reader descheduled for longer than the buffers last (8 at 60 fps:
        // 133 ms) otherwise met real-time drops, bursts of stale frames it skipped, and faults
        // frames early: the tests failed at random (the flake, issue 16).
        setenv("LUMAR_VCAM_PACED", "1", 1);
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

TEST_F(V4l2SourceTest, NegotiationOrderIsNv12YuyvMjpegGrey)
{
    struct Offer {
        const char* formats;
        uint32_t expected;
    };
    for (Offer offer : {Offer{"GREY,MJPG,YUYV,NV12", V4L2_PIX_FMT_NV12}, Offer{"GREY,MJPG,YUYV", V4L2_PIX_FMT_YUYV},
                        Offer{"GREY,MJPG", V4L2_PIX_FMT_MJPEG}, Offer{"GREY", V4L2_PIX_FMT_GREY}}) {
        setenv("LUMAR_VCAM_FORMATS", offer.formats, 1);
        V4l2Source source(options());
        EXPECT_EQ(source.pixelFormat(), offer.expected) << offer.formats;
    }
}

TEST_F(V4l2SourceTest, ConfiguredFormatWinsOrFailsClearly)
{
    V4l2Options o = options();
    o.pixelFormat = pixelFormatFromName("mjpeg"); // the device offers all four
    {
        V4l2Source source(o);
        EXPECT_EQ(source.pixelFormat(), uint32_t(V4L2_PIX_FMT_MJPEG));
    }
    setenv("LUMAR_VCAM_FORMATS", "YUYV", 1);
    o.pixelFormat = pixelFormatFromName("nv12");
    try {
        V4l2Source source(o);
        FAIL() << "a format the device lacks was accepted";
    } catch (const RuntimeError& error) {
        EXPECT_NE(std::string(error.what()).find("camera.format NV12 is not offered (offers YUYV"), std::string::npos)
            << error.what();
    }
    EXPECT_THROW(pixelFormatFromName("rgb24"), InputError);
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

// MJPEG at quality 95 (4:2:2): inside the bars within 2 code values (as the decoder's own
// test), the moving block where the sequence number puts it, 60 frames without a drop.
TEST_F(V4l2SourceTest, StreamsMjpegDecodedWithinTolerance)
{
    setenv("LUMAR_VCAM_FORMATS", "MJPG", 1);
    V4l2Source source(options());
    ASSERT_EQ(source.pixelFormat(), uint32_t(V4L2_PIX_FMT_MJPEG));
    Frame frame;
    for (int i = 0; i < 60; ++i) {
        ASSERT_TRUE(source.next(frame));
        ASSERT_EQ(frame.rgb.width, 640);
        ASSERT_EQ(frame.luma.height, 480);
        EXPECT_LE(worstBarError(frame, false), 2) << "frame " << i;
        const int left = vcam::blockLeft(int64_t(frame.sequence), 640);
        const int row = (vcam::blockBandTop(480) + 480) / 2;
        EXPECT_GT(*frame.luma.at(left + vcam::kBlockWidth / 2, row), 250) << "frame " << i;
        EXPECT_LT(*frame.luma.at((left + vcam::kBlockWidth + 8) % 640, row), 5) << "frame " << i;
    }
    EXPECT_EQ(frame.sequence, 59u);
    EXPECT_EQ(source.framesDropped(), 0u);
    EXPECT_EQ(source.framesCorrupt(), 0u);
}

TEST_F(V4l2SourceTest, CorruptMjpegFramesAreCountedAndSkipped)
{
    setenv("LUMAR_VCAM_FORMATS", "MJPG", 1);
    setenv("LUMAR_VCAM_FAULT_CORRUPT_EVERY", "4", 1);
    V4l2Source source(options());
    Frame frame;
    for (int i = 0; i < 30; ++i) {
        ASSERT_NO_THROW(source.next(frame)) << "frame " << i;
        EXPECT_NE((frame.sequence + 1) % 4, 0u) << "a corrupt frame was delivered";
        EXPECT_LE(worstBarError(frame, false), 2);
    }
    // Sequences s <= last with (s + 1) divisible by 4 were garbled by the device.
    EXPECT_EQ(source.framesCorrupt(), (frame.sequence + 1) / 4);
    EXPECT_GE(source.framesCorrupt(), 9u);
    EXPECT_EQ(source.framesDropped(), 0u); // corrupt frames are not sequence gaps
}

TEST_F(V4l2SourceTest, OnlyCorruptFramesTimeOutLikeNoFrames)
{
    setenv("LUMAR_VCAM_FORMATS", "MJPG", 1);
    setenv("LUMAR_VCAM_FAULT_CORRUPT_EVERY", "1", 1); // every frame garbled
    V4l2Options o = options();
    o.frameTimeoutMs = 300;
    V4l2Source source(o);
    Frame frame;
    try {
        source.next(frame);
        FAIL() << "a corrupt frame was delivered";
    } catch (const RuntimeError& error) {
        EXPECT_EQ(std::string(error.what()), std::string(devicePath()) + ": no frame for 0.3 s (only corrupt ones)");
    }
    // 300 ms at 60 fps: at most 19 frames (the paced device makes none faster), each counted.
    // How many this process got to decode in 300 ms is a timing (a loaded machine decoded 12),
    // so the floor is one counted frame, not 15.
    EXPECT_GE(source.framesCorrupt(), 1u);
    EXPECT_LE(source.framesCorrupt(), 19u);
}

TEST_F(V4l2SourceTest, ShortMjpegFramesAreCountedAsCorrupt)
{
    setenv("LUMAR_VCAM_FORMATS", "MJPG", 1);
    setenv("LUMAR_VCAM_FAULT_SHORT_EVERY", "3", 1); // bytesused halved: a truncated JPEG
    V4l2Source source(options());
    Frame frame;
    for (int i = 0; i < 12; ++i) {
        ASSERT_TRUE(source.next(frame));
        EXPECT_NE((frame.sequence + 1) % 3, 0u);
    }
    EXPECT_EQ(source.framesCorrupt(), (frame.sequence + 1) / 3);
}

// Reads a control through a second handle on the device, as another program would.
int32_t readControl(uint32_t id)
{
    const int fd = ::open(devicePath(), O_RDWR);
    EXPECT_GE(fd, 0);
    v4l2_control control{id, 0};
    EXPECT_EQ(::ioctl(fd, VIDIOC_G_CTRL, &control), 0) << std::hex << id;
    ::close(fd);
    return control.value;
}

TEST_F(V4l2SourceTest, ControlsFromTheConfigAreAppliedAndClamped)
{
    V4l2Options o = options();
    o.controls.exposureUs = 10'000;  // 100 units of 100 us
    o.controls.gain = 300;           // the device's range is 0..255: clamped
    o.controls.whiteBalanceK = 5003; // step 10: snapped to 5000
    o.controls.powerLineHz = 60;
    V4l2Source source(o);
    EXPECT_EQ(readControl(V4L2_CID_EXPOSURE_AUTO), V4L2_EXPOSURE_MANUAL);
    EXPECT_EQ(readControl(V4L2_CID_EXPOSURE_ABSOLUTE), 100);
    EXPECT_EQ(readControl(V4L2_CID_GAIN), 255);
    EXPECT_EQ(readControl(V4L2_CID_AUTO_WHITE_BALANCE), 0);
    EXPECT_EQ(readControl(V4L2_CID_WHITE_BALANCE_TEMPERATURE), 5000);
    EXPECT_EQ(readControl(V4L2_CID_POWER_LINE_FREQUENCY), V4L2_CID_POWER_LINE_FREQUENCY_60HZ);
    Frame frame;
    EXPECT_TRUE(source.next(frame)); // still streams

    // "auto": the camera's automatic modes (a UVC camera has aperture priority, not full auto).
    const int fd = ::open(devicePath(), O_RDWR);
    ASSERT_GE(fd, 0);
    CameraControlsConfig automatic;
    automatic.exposureUs = CameraControlsConfig::kAuto;
    automatic.whiteBalanceK = CameraControlsConfig::kAuto;
    automatic.powerLineHz = 0;
    const auto applied = applyCameraControls(devicePath(), fd, automatic);
    ::close(fd);
    ASSERT_EQ(applied.size(), 3u);
    for (const AppliedControl& control : applied) {
        EXPECT_TRUE(control.set) << control.name;
    }
    EXPECT_EQ(readControl(V4L2_CID_EXPOSURE_AUTO), V4L2_EXPOSURE_APERTURE_PRIORITY);
    EXPECT_EQ(readControl(V4L2_CID_AUTO_WHITE_BALANCE), 1);
    EXPECT_EQ(readControl(V4L2_CID_POWER_LINE_FREQUENCY), V4L2_CID_POWER_LINE_FREQUENCY_DISABLED);
}

TEST_F(V4l2SourceTest, ControlsTheDeviceLacksAreWarningsNotErrors)
{
    // /dev/null answers every V4L2 ioctl with ENOTTY: a camera without any controls.
    const int fd = ::open("/dev/null", O_RDWR);
    ASSERT_GE(fd, 0);
    CameraControlsConfig config;
    config.exposureUs = 20'000;
    config.gain = 10;
    config.whiteBalanceK = 4000;
    config.powerLineHz = 50;
    std::vector<AppliedControl> applied;
    ASSERT_NO_THROW(applied = applyCameraControls("/dev/null", fd, config));
    ::close(fd);
    ASSERT_EQ(applied.size(), 6u); // exposure mode + time, gain, white balance mode + temperature, power line
    for (const AppliedControl& control : applied) {
        EXPECT_FALSE(control.set) << control.name;
    }
}

TEST_F(V4l2SourceTest, SourceChangeRestartsTheStreamAtTheNewSize)
{
    setenv("LUMAR_VCAM_SOURCE_CHANGE_AT", "10", 1);
    setenv("LUMAR_VCAM_SOURCE_CHANGE_SIZE", "1280x720", 1);
    for (const char* format : {"NV12", "MJPG"}) {
        setenv("LUMAR_VCAM_FORMATS", format, 1);
        V4l2Source source(options(640, 480));
        Frame frame;
        for (int i = 0; i < 10; ++i) {
            ASSERT_TRUE(source.next(frame));
            ASSERT_EQ(frame.rgb.width, 640) << format;
        }
        EXPECT_EQ(source.sourceChanges(), 0);
        for (int i = 0; i < 10; ++i) {
            ASSERT_TRUE(source.next(frame));
            ASSERT_EQ(frame.rgb.width, 1280) << format;
            ASSERT_EQ(frame.luma.height, 720) << format;
            EXPECT_LE(worstBarError(frame, false), 2) << format;
        }
        EXPECT_EQ(source.sourceChanges(), 1) << format;
        EXPECT_EQ(source.width(), 1280);
        EXPECT_EQ(source.height(), 720);
        EXPECT_EQ(frame.sequence, 9u); // the restarted stream counts from 0 again
        EXPECT_EQ(source.framesDropped(), 0u);
    }
}

TEST_F(V4l2SourceTest, SourceChangeIsAnErrorForAFixedSizeCaller)
{
    setenv("LUMAR_VCAM_SOURCE_CHANGE_AT", "5", 1);
    V4l2Options o = options(640, 480);
    o.followResolutionChanges = false;
    V4l2Source source(o);
    Frame frame;
    for (int i = 0; i < 5; ++i) {
        ASSERT_TRUE(source.next(frame));
    }
    try {
        source.next(frame);
        FAIL() << "no error for the resolution change";
    } catch (const RuntimeError& error) {
        EXPECT_NE(std::string(error.what()).find("changed resolution from 640x480 to 1280x720"), std::string::npos)
            << error.what();
    }
}

// A raw (NV12/YUYV) frame converted on the CPU from wherever its planes live, so the colour
// bars and the block can be checked as for converted frames.
void convertRawPlanes(Frame& frame)
{
    const YCbCrImage& raw = frame.ycbcr;
    const YCbCrConverter converter(raw.colorimetry);
    Image8 luma;
    if (raw.layout == YCbCrLayout::Nv12)
        converter.convertNv12(raw.planeData(0), raw.stride0, raw.planeData(1), raw.stride1, raw.width, raw.height,
                              frame.rgb, luma);
    else
        converter.convertYuyv(raw.planeData(0), raw.stride0, raw.width, raw.height, frame.rgb, luma);
    EXPECT_EQ(luma.data, frame.luma.data); // the tracker's luma is read from the same planes
}

V4l2Options zeroCopy(V4l2Options o)
{
    o.rawYcbcr = true;
    o.zeroCopy = true;
    return o;
}

TEST_F(V4l2SourceTest, ZeroCopyFramesBorrowTheDriversExportedBuffers)
{
    for (const uint32_t format : {V4L2_PIX_FMT_NV12, V4L2_PIX_FMT_YUYV}) {
        const std::string name = fourccName(format);
        setenv("LUMAR_VCAM_FORMATS", name.c_str(), 1);
        V4l2Source source(zeroCopy(options()));
        ASSERT_EQ(source.pixelFormat(), format);
        // The requested 8, plus the frames in flight.
        EXPECT_EQ(source.bufferCount(), size_t(8 + V4l2Source::kLentBuffers)) << name;
        EXPECT_EQ(source.buffersExported(), source.bufferCount()) << name;
        Frame frame;
        for (int i = 0; i < 30; ++i) {
            ASSERT_TRUE(source.next(frame));
            const YCbCrImage& raw = frame.ycbcr;
            ASSERT_TRUE(raw.buffer) << name << " frame " << i;
            EXPECT_TRUE(raw.plane0.empty());
            EXPECT_TRUE(raw.buffer->exported());
            EXPECT_EQ(raw.buffer->drmFourcc(), format); // DRM and V4L2 spell NV12 and YUYV alike
            EXPECT_GE(raw.stride0, size_t(raw.width) * (format == V4L2_PIX_FMT_NV12 ? 1 : 2));
            if (format == V4L2_PIX_FMT_NV12) {
                EXPECT_EQ(raw.buffer->planes()[1].offset, raw.stride0 * size_t(raw.height));
                EXPECT_EQ(raw.buffer->planes()[1].data, raw.buffer->planes()[0].data + raw.stride0 * raw.height);
            }
            // The exported descriptor is the buffer's memory (the virtual camera's is a memfd,
            // which pread reads; a kernel dmabuf would need mmap).
            std::vector<uint8_t> exported(raw.stride0 * 4);
            ASSERT_EQ(::pread(raw.buffer->planes()[0].dmabufFd, exported.data(), exported.size(), 0),
                      ssize_t(exported.size()));
            EXPECT_EQ(std::memcmp(exported.data(), raw.planeData(0), exported.size()), 0) << name;
            convertRawPlanes(frame);
            EXPECT_LE(worstBarError(frame, false), 2) << name << " frame " << i;
            EXPECT_TRUE(blockWhereSequenceSays(frame)) << name << " frame " << i;
            // Only this frame holds a buffer: the one it held before went back to the driver.
            EXPECT_EQ(source.buffersLent(), 1u) << name << " frame " << i;
        }
        EXPECT_EQ(source.framesDropped(), 0u) << name;
    }
}

// Frames kept longer than the stream has spare buffers for: the driver keeps two to fill and
// the rest arrive as copies; the held frames are never overwritten; once let go, their
// buffers are lent again.
TEST_F(V4l2SourceTest, HeldZeroCopyFramesKeepTheirBuffersWhileTheStreamGoesOn)
{
    setenv("LUMAR_VCAM_FORMATS", "NV12", 1);
    V4l2Source source(zeroCopy(options()));
    const size_t buffers = source.bufferCount();
    std::vector<Frame> held(buffers + 4);
    for (Frame& frame : held)
        ASSERT_TRUE(source.next(frame));
    EXPECT_EQ(source.buffersLent(), buffers - 2); // all but the two the driver keeps filling
    size_t copies = 0;
    for (Frame& frame : held) {
        copies += frame.ycbcr.buffer ? 0 : 1;
        if (!frame.ycbcr.buffer) {
            EXPECT_FALSE(frame.ycbcr.plane0.empty());
        }
        convertRawPlanes(frame);
        EXPECT_TRUE(blockWhereSequenceSays(frame)) << "frame " << frame.sequence;
        EXPECT_LE(worstBarError(frame, false), 2) << "frame " << frame.sequence;
    }
    EXPECT_EQ(copies, held.size() - (buffers - 2));
    held.clear();
    Frame frame;
    ASSERT_TRUE(source.next(frame));
    EXPECT_TRUE(frame.ycbcr.buffer);
    EXPECT_EQ(source.buffersLent(), 1u);
    EXPECT_EQ(source.framesDropped(), 0u);
}

// A frame may outlive its source (a camera reopened after an unplug while the last frame is
// still on screen): its buffer's mapping goes with the frame, not with the source.
TEST_F(V4l2SourceTest, ZeroCopyFramesOutliveTheirSource)
{
    setenv("LUMAR_VCAM_FORMATS", "YUYV", 1);
    Frame frame;
    {
        V4l2Source source(zeroCopy(options()));
        ASSERT_TRUE(source.next(frame));
        ASSERT_TRUE(source.next(frame));
    }
    ASSERT_TRUE(frame.ycbcr.buffer);
    EXPECT_EQ(frame.ycbcr.buffer.use_count(), 1);
    convertRawPlanes(frame);
    EXPECT_LE(worstBarError(frame, false), 2);
    EXPECT_TRUE(blockWhereSequenceSays(frame));
}

TEST_F(V4l2SourceTest, WithoutZeroCopyThePlanesAreCopied)
{
    setenv("LUMAR_VCAM_FORMATS", "NV12", 1);
    V4l2Options o = zeroCopy(options());
    o.zeroCopy = false;
    V4l2Source source(o);
    EXPECT_EQ(source.bufferCount(), 8u);
    EXPECT_EQ(source.buffersExported(), 0u);
    Frame frame;
    ASSERT_TRUE(source.next(frame));
    EXPECT_FALSE(frame.ycbcr.buffer);
    EXPECT_EQ(frame.ycbcr.plane0.size(), size_t(640 * 480));
    convertRawPlanes(frame);
    EXPECT_LE(worstBarError(frame, false), 2);
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
