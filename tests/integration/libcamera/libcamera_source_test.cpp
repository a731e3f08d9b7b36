// The libcamera backend against whatever this machine has. Without cameras (CI, containers:
// no /dev/media*), opening must fail at once with CameraUnavailable and a one-line reason —
// not a crash, not a hang — and the shared camera manager must start and stop again cleanly
// (libcamera aborts on a second manager in one process). With a camera, frames must stream.
#include <chrono>

#include <gtest/gtest.h>

#include "capture/factory/capture_factory.h"
#include "capture/libcamera/libcamera_manager.h"
#include "capture/libcamera/libcamera_probe.h"
#include "capture/libcamera/libcamera_source.h"
#include "capture/reconnecting_source.h"
#include "config/config.h"
#include "core/error.h"
#include "core/frame.h"

namespace lumar {
namespace {

bool haveCameras()
{
    return !probeLibcamera().cameras.empty();
}

double secondsSince(std::chrono::steady_clock::time_point start)
{
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

TEST(LibcameraSource, NoCamerasIsCameraUnavailableWithAOneLineReason)
{
    if (haveCameras())
        GTEST_SKIP() << "this machine has libcamera cameras";
    // Twice: the manager is stopped with the failed source and must start again.
    for (int attempt = 0; attempt < 2; ++attempt) {
        const auto start = std::chrono::steady_clock::now();
        try {
            LibcameraSource source(LibcameraOptions{});
            FAIL() << "opened a camera that the probe did not list";
        } catch (const CameraUnavailable& e) {
            const std::string message = e.what();
            EXPECT_EQ(message.rfind("libcamera: no cameras found (libcamera v", 0), 0u) << message;
            EXPECT_NE(message.find("media devices in /dev)"), std::string::npos) << message;
            EXPECT_EQ(message.find('\n'), std::string::npos) << message;
        }
        EXPECT_LT(secondsSince(start), 5.0);
    }
}

TEST(LibcameraSource, OpenedThroughTheConfigLikeV4l2)
{
    if (haveCameras())
        GTEST_SKIP() << "this machine has libcamera cameras";
    CameraConfig config;
    config.source = "libcamera";
    const auto start = std::chrono::steady_clock::now();
    // The first open is not retried: the caller learns at once that there is no camera.
    EXPECT_THROW(openCaptureSource(config), CameraUnavailable);
    EXPECT_LT(secondsSince(start), 5.0);
}

TEST(LibcameraSource, AFormatLibcameraCamerasAreNotReadInIsBadInputBeforeAnyCameraOpens)
{
    CameraConfig config;
    config.source = "libcamera";
    config.format = "mjpeg"; // valid for v4l2, not for libcamera
    try {
        openCaptureSource(config);
        FAIL() << "accepted camera.format mjpeg for libcamera";
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("camera.format: 'mjpeg'"), std::string::npos) << e.what();
    }
}

TEST(LibcameraSource, ProbeAndSourceShareOneManager)
{
    const auto first = acquireCameraManager();
    const auto second = acquireCameraManager();
    EXPECT_EQ(first.get(), second.get());
    // A probe while the manager is held reuses it (a second manager would abort the process).
    const LibcameraProbeInfo info = probeLibcamera();
    EXPECT_EQ(info.version.rfind("libcamera v", 0), 0u) << info.version;
    if (info.cameras.empty()) {
        EXPECT_EQ(info.error, noLibcameraCamerasMessage());
    }
}

TEST(LibcameraSource, StreamsFramesFromARealCamera)
{
    if (!haveCameras())
        GTEST_SKIP() << "no libcamera camera on this machine";
    LibcameraOptions options;
    options.width = 640;
    options.height = 480;
    LibcameraSource source(options);
    Frame frame;
    int64_t lastTimestamp = 0;
    for (int i = 0; i < 20; ++i) {
        ASSERT_TRUE(source.next(frame));
        EXPECT_EQ(frame.rgb.width, source.width());
        EXPECT_EQ(frame.luma.height, source.height());
        EXPECT_GT(frame.timestampNs, lastTimestamp);
        lastTimestamp = frame.timestampNs;
    }
}

// camera.convert = "gpu" with zero-copy: a YCbCr stream's frames carry planes (copied or
// lent); a packed RGB stream (vimc offers nothing else) must still arrive as converted RGB,
// never as planes or a lent buffer the renderer would take for YCbCr.
TEST(LibcameraSource, AskedForGpuConversionEveryFrameIsEitherYcbcrPlanesOrRgb)
{
    if (!haveCameras())
        GTEST_SKIP() << "no libcamera camera on this machine";
    LibcameraOptions options;
    options.width = 640;
    options.height = 480;
    options.rawYcbcr = true;
    options.zeroCopy = true;
    LibcameraSource source(options);
    Frame frame;
    for (int i = 0; i < 10; ++i) {
        ASSERT_TRUE(source.next(frame));
        EXPECT_EQ(frame.luma.width, source.width());
        EXPECT_EQ(frame.luma.height, source.height());
        if (frame.ycbcr.empty()) {
            EXPECT_EQ(frame.ycbcr.buffer, nullptr);
            EXPECT_EQ(frame.rgb.width, source.width());
            EXPECT_EQ(frame.rgb.height, source.height());
            EXPECT_EQ(frame.rgb.channels, 3);
        } else {
            EXPECT_EQ(frame.ycbcr.width, source.width());
            EXPECT_EQ(frame.ycbcr.height, source.height());
        }
    }
}

} // namespace
} // namespace lumar
