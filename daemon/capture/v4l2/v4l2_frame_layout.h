// What a V4L2 driver's answers mean for the frames that arrive, as pure functions of those
// answers: the negotiated format (VIDIOC_S_FMT's v4l2_pix_format) checked into a frame
// layout, a dequeued buffer (flags, bytesused, length) checked against it, and the buffer's
// bytes converted (or JPEG-decoded) into a frame. V4l2Source calls them with what the device
// said; the fuzz target tests/fuzz/fuzz_v4l2_frame.cpp with what a broken or hostile driver
// might say (issue 16).
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>

#include <linux/videodev2.h>

#include "capture/v4l2/mjpeg_decoder.h"
#include "capture/v4l2/ycbcr_to_rgb.h"
#include "core/frame.h"

namespace lumar {

struct V4l2FrameLayout {
    uint32_t pixelFormat = 0; // NV12, YUYV, MJPEG or GREY
    int width = 0;
    int height = 0;
    size_t bytesPerLine = 0; // of the luma (or packed) plane; NV12's chroma plane has the same
    size_t imageSize = 0;    // the bytes a raw frame needs; 0 for MJPEG (its size varies)
};

// The largest frame side and raw image a driver may hand us: the config's own limit on
// camera.width/height, and 8192 x 8192 YUYV with generous padding. Beyond them a driver's
// answer is garbage (a side above INT_MAX would turn negative in the int sizes frames use).
inline constexpr uint32_t kMaxV4l2Side = 8192;
inline constexpr size_t kMaxV4l2ImageBytes = size_t(256) << 20;

// The layout of `accepted`, the format the driver returned for a request of `pixelFormat`.
// Throws RuntimeError ("DEVICE: ...") when the driver replaced the format, or returned sizes,
// strides or an image size the frames cannot be read with.
V4l2FrameLayout frameLayoutOf(const std::string& device, const v4l2_pix_format& accepted, uint32_t pixelFormat);

// Why a dequeued buffer (its flags and bytesused, in a mapping of `length` bytes) cannot be
// converted: the error flag, fewer bytes than the image needs, more than the mapping holds.
// Empty when it can.
std::string bufferDefect(const V4l2FrameLayout& layout, uint32_t flags, size_t bytesUsed, size_t length);

// Converts one good buffer (bufferDefect() empty; `data` holds `bytesUsed` bytes) into the
// frame's sRGB and luma, or with `keepRaw` an NV12/YUYV buffer's planes into frame.ycbcr plus
// luma. `mjpeg` decodes MJPEG (required for it). Returns false, with the reason in `error`,
// for data that does not decode (MJPEG only); raw formats always convert.
bool convertV4l2Frame(const V4l2FrameLayout& layout, const YCbCrConverter& converter, MjpegDecoder* mjpeg, bool keepRaw,
                      const uint8_t* data, size_t bytesUsed, Frame& frame, std::string& error);

} // namespace lumar
