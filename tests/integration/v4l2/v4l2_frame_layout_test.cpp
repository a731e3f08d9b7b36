// The checks on a driver's answers (capture/v4l2/v4l2_frame_layout.h): a negotiated format
// the frames cannot be read with, and a buffer whose size does not fit, are refused before a
// byte is converted (issue 16; tests/fuzz/fuzz_v4l2_frame.cpp feeds them fuzzed values).
#include <gtest/gtest.h>

#include "capture/v4l2/v4l2_frame_layout.h"
#include "core/error.h"

namespace lumar {
namespace {

v4l2_pix_format format(uint32_t fourcc, uint32_t width, uint32_t height, uint32_t bytesPerLine, uint32_t sizeImage)
{
    v4l2_pix_format f{};
    f.pixelformat = fourcc;
    f.width = width;
    f.height = height;
    f.bytesperline = bytesPerLine;
    f.sizeimage = sizeImage;
    return f;
}

TEST(V4l2FrameLayout, PaddedRowsGiveTheImageSizeTheConvertersRead)
{
    const V4l2FrameLayout nv12 =
        frameLayoutOf("cam", format(V4L2_PIX_FMT_NV12, 32, 24, 64, 64 * 36), V4L2_PIX_FMT_NV12);
    EXPECT_EQ(nv12.width, 32);
    EXPECT_EQ(nv12.height, 24);
    EXPECT_EQ(nv12.bytesPerLine, 64u);
    EXPECT_EQ(nv12.imageSize, 64u * 36u);
    const V4l2FrameLayout mjpeg = frameLayoutOf("cam", format(V4L2_PIX_FMT_MJPEG, 64, 48, 0, 9000), V4L2_PIX_FMT_MJPEG);
    EXPECT_EQ(mjpeg.imageSize, 0u); // a JPEG's size varies
}

TEST(V4l2FrameLayout, FormatsTheFramesCannotBeReadWithAreRefused)
{
    const auto refused = [](const v4l2_pix_format& f, uint32_t asked) {
        EXPECT_THROW(frameLayoutOf("cam", f, asked), RuntimeError)
            << f.width << "x" << f.height << " " << f.bytesperline << " " << f.sizeimage;
    };
    refused(format(V4L2_PIX_FMT_YUYV, 32, 24, 64, 64 * 24), V4L2_PIX_FMT_NV12);     // another format
    refused(format(V4L2_PIX_FMT_YUYV, 32, 24, 63, 64 * 24), V4L2_PIX_FMT_YUYV);     // rows too short
    refused(format(V4L2_PIX_FMT_NV12, 32, 24, 32, 32 * 24), V4L2_PIX_FMT_NV12);     // no chroma room
    refused(format(V4L2_PIX_FMT_NV12, 32, 23, 32, 32 * 36), V4L2_PIX_FMT_NV12);     // odd NV12 height
    refused(format(V4L2_PIX_FMT_GREY, 0, 24, 32, 32 * 24), V4L2_PIX_FMT_GREY);      // empty
    refused(format(V4L2_PIX_FMT_MJPEG, 64, 48, 0, 0), V4L2_PIX_FMT_MJPEG);          // no room for a JPEG
    refused(format(V4L2_PIX_FMT_GREY, 8194, 2, 8194, 8194 * 2), V4L2_PIX_FMT_GREY); // side above 8192
    // A side above INT_MAX would be a negative int in every frame size after it.
    refused(format(V4L2_PIX_FMT_YUYV, 0x80000000u, 2, 0xFFFFFFFFu, 0xFFFFFFFFu), V4L2_PIX_FMT_YUYV);
    // Rows padded to 4 GiB: the image would not fit any mapping lumar accepts.
    refused(format(V4L2_PIX_FMT_GREY, 16, 16, 0x40000000u, 0xFFFFFFFFu), V4L2_PIX_FMT_GREY);
}

TEST(V4l2FrameLayout, BuffersThatDoNotHoldAFrameAreDefects)
{
    const V4l2FrameLayout grey = frameLayoutOf("cam", format(V4L2_PIX_FMT_GREY, 16, 16, 16, 256), V4L2_PIX_FMT_GREY);
    EXPECT_EQ(bufferDefect(grey, 0, 256, 256), "");
    EXPECT_NE(bufferDefect(grey, V4L2_BUF_FLAG_ERROR, 256, 256), "");
    EXPECT_NE(bufferDefect(grey, 0, 255, 256), "");  // short
    EXPECT_NE(bufferDefect(grey, 0, 4096, 256), ""); // more than the mapping holds
    const V4l2FrameLayout mjpeg = frameLayoutOf("cam", format(V4L2_PIX_FMT_MJPEG, 64, 48, 0, 9000), V4L2_PIX_FMT_MJPEG);
    EXPECT_NE(bufferDefect(mjpeg, 0, 0, 9000), ""); // an empty JPEG
    EXPECT_EQ(bufferDefect(mjpeg, 0, 1200, 9000), "");
}

} // namespace
} // namespace lumar
