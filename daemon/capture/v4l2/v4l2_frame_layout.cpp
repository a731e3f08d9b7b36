#include "capture/v4l2/v4l2_frame_layout.h"

#include <algorithm>

#include "capture/v4l2/v4l2_ioctl.h"
#include "core/error.h"
#include "core/ycbcr_image.h"

namespace lumar {

V4l2FrameLayout frameLayoutOf(const std::string& device, const v4l2_pix_format& accepted, uint32_t pixelFormat)
{
    if (accepted.pixelformat != pixelFormat) {
        throw RuntimeError(device + ": the driver replaced " + fourccName(pixelFormat) + " by " +
                           fourccName(accepted.pixelformat));
    }
    const bool compressed = pixelFormat == V4L2_PIX_FMT_MJPEG;
    const bool subsampled = pixelFormat != V4L2_PIX_FMT_GREY && !compressed;
    const bool verticallySubsampled = pixelFormat == V4L2_PIX_FMT_NV12;
    const size_t bytesPerPixel = pixelFormat == V4L2_PIX_FMT_YUYV ? 2 : 1;
    if (accepted.width == 0 || accepted.height == 0 || accepted.width > kMaxV4l2Side ||
        accepted.height > kMaxV4l2Side || (subsampled && accepted.width % 2 != 0) ||
        (verticallySubsampled && accepted.height % 2 != 0) ||
        (!compressed && accepted.bytesperline < accepted.width * bytesPerPixel) ||
        (compressed && accepted.sizeimage == 0)) {
        throw RuntimeError(device + ": the driver returned an unusable format (" + std::to_string(accepted.width) +
                           "x" + std::to_string(accepted.height) + ", " + std::to_string(accepted.bytesperline) +
                           " bytes per line)");
    }
    V4l2FrameLayout layout;
    layout.pixelFormat = pixelFormat;
    layout.width = int(accepted.width);
    layout.height = int(accepted.height);
    layout.bytesPerLine = accepted.bytesperline;
    const size_t planeSize = layout.bytesPerLine * size_t(layout.height); // both below 2^32: no overflow
    layout.imageSize = compressed ? 0 : verticallySubsampled ? planeSize + planeSize / 2 : planeSize;
    if (layout.imageSize > kMaxV4l2ImageBytes || (compressed && accepted.sizeimage > kMaxV4l2ImageBytes)) {
        throw RuntimeError(device + ": the driver's frames would take " +
                           std::to_string(compressed ? size_t(accepted.sizeimage) : layout.imageSize) +
                           " bytes each (at most " + std::to_string(kMaxV4l2ImageBytes) + " accepted)");
    }
    if (accepted.sizeimage < layout.imageSize) {
        throw RuntimeError(device + ": the driver's image size " + std::to_string(accepted.sizeimage) +
                           " is smaller than the format needs (" + std::to_string(layout.imageSize) + ")");
    }
    return layout;
}

std::string bufferDefect(const V4l2FrameLayout& layout, uint32_t flags, size_t bytesUsed, size_t length)
{
    const bool error = (flags & V4L2_BUF_FLAG_ERROR) != 0;
    if (!error && bytesUsed >= std::max<size_t>(layout.imageSize, 1) && bytesUsed <= length)
        return {};
    return std::to_string(bytesUsed) + " bytes of " +
           (layout.imageSize > 0 ? std::to_string(layout.imageSize) : "a JPEG") +
           (bytesUsed > length ? " in a buffer of " + std::to_string(length) : "") + (error ? ", error flag" : "");
}

namespace {

// Copies an NV12/YUYV buffer's planes into frame.ycbcr and fills frame.luma.
void keepRawPlanes(const V4l2FrameLayout& layout, const YCbCrConverter& converter, const uint8_t* data, Frame& frame)
{
    YCbCrImage& raw = frame.ycbcr;
    raw.width = layout.width;
    raw.height = layout.height;
    raw.colorimetry = converter.colorimetry();
    const size_t width = size_t(layout.width);
    if (layout.pixelFormat == V4L2_PIX_FMT_NV12) {
        raw.layout = YCbCrLayout::Nv12;
        copyPlaneRows(data, layout.bytesPerLine, width, layout.height, raw.plane0);
        copyPlaneRows(data + layout.bytesPerLine * size_t(layout.height), layout.bytesPerLine, width, layout.height / 2,
                      raw.plane1);
        raw.stride0 = raw.stride1 = width;
        converter.convertLuma(data, layout.bytesPerLine, 1, layout.width, layout.height, frame.luma);
    } else {
        raw.layout = YCbCrLayout::Yuyv;
        copyPlaneRows(data, layout.bytesPerLine, width * 2, layout.height, raw.plane0);
        raw.plane1.clear();
        raw.stride0 = width * 2;
        raw.stride1 = 0;
        converter.convertLuma(data, layout.bytesPerLine, 2, layout.width, layout.height, frame.luma);
    }
}

} // namespace

bool convertV4l2Frame(const V4l2FrameLayout& layout, const YCbCrConverter& converter, MjpegDecoder* mjpeg, bool keepRaw,
                      const uint8_t* data, size_t bytesUsed, Frame& frame, std::string& error)
{
    const int width = layout.width, height = layout.height;
    const size_t stride = layout.bytesPerLine;
    const bool raw = layout.pixelFormat == V4L2_PIX_FMT_NV12 || layout.pixelFormat == V4L2_PIX_FMT_YUYV;
    if (keepRaw && raw) {
        keepRawPlanes(layout, converter, data, frame);
        return true;
    }
    // A frame object recycled from a raw frame must not carry stale planes.
    frame.ycbcr.layout = YCbCrLayout::None;
    switch (layout.pixelFormat) {
    case V4L2_PIX_FMT_MJPEG:
        if (!mjpeg)
            throw RuntimeError("an MJPEG frame without a decoder");
        return mjpeg->decode(data, bytesUsed, width, height, frame.rgb, frame.luma, error);
    case V4L2_PIX_FMT_YUYV:
        converter.convertYuyv(data, stride, width, height, frame.rgb, frame.luma);
        break;
    case V4L2_PIX_FMT_NV12:
        converter.convertNv12(data, stride, data + stride * size_t(height), stride, width, height, frame.rgb,
                              frame.luma);
        break;
    default:
        converter.convertGrey(data, stride, width, height, frame.rgb, frame.luma);
        break;
    }
    return true;
}

} // namespace lumar
