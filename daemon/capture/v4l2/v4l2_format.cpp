#include "capture/v4l2/v4l2_format.h"

#include <algorithm>
#include <cerrno>
#include <cstdlib>

#include "capture/v4l2/v4l2_ioctl.h"
#include "core/error.h"

namespace lumar {

const std::vector<uint32_t>& supportedPixelFormats()
{
    static const std::vector<uint32_t> formats{V4L2_PIX_FMT_NV12, V4L2_PIX_FMT_YUYV, V4L2_PIX_FMT_MJPEG,
                                               V4L2_PIX_FMT_GREY};
    return formats;
}

uint32_t pixelFormatFromName(const std::string& name)
{
    if (name == "auto")
        return 0;
    if (name == "nv12")
        return V4L2_PIX_FMT_NV12;
    if (name == "yuyv")
        return V4L2_PIX_FMT_YUYV;
    if (name == "mjpeg")
        return V4L2_PIX_FMT_MJPEG;
    if (name == "grey")
        return V4L2_PIX_FMT_GREY;
    throw InputError("camera.format: unknown format '" + name + "' (expected auto, nv12, yuyv, mjpeg or grey)");
}

uint32_t choosePixelFormat(const std::vector<uint32_t>& deviceFormats, uint32_t required)
{
    if (required != 0) {
        return std::find(deviceFormats.begin(), deviceFormats.end(), required) != deviceFormats.end() ? required : 0;
    }
    for (uint32_t preferred : supportedPixelFormats()) {
        if (std::find(deviceFormats.begin(), deviceFormats.end(), preferred) != deviceFormats.end()) {
            return preferred;
        }
    }
    return 0;
}

FrameSize chooseFrameSize(const std::vector<FrameSize>& sizes, FrameSize requested)
{
    // Unsigned: a driver's 0xffffffff x 0xffffffff overflowed int64_t (fuzz_v4l2_driver).
    const auto area = [](FrameSize s) { return uint64_t(s.width) * uint64_t(s.height); };
    const auto distance = [](uint64_t a, uint64_t b) { return a > b ? a - b : b - a; };
    FrameSize best = sizes.front();
    for (const FrameSize& s : sizes) {
        if (s.width == requested.width && s.height == requested.height) {
            return s;
        }
        const uint64_t difference = distance(area(s), area(requested));
        const uint64_t bestDifference = distance(area(best), area(requested));
        if (difference < bestDifference || (difference == bestDifference && area(s) > area(best))) {
            best = s;
        }
    }
    return best;
}

YCbCrColorimetry colorimetryOf(const v4l2_pix_format& format)
{
    const auto colorspace = format.colorspace;
    unsigned encoding = format.ycbcr_enc;
    if (encoding == V4L2_YCBCR_ENC_DEFAULT) {
        encoding = V4L2_MAP_YCBCR_ENC_DEFAULT(colorspace);
    }
    unsigned quantization = format.quantization;
    if (quantization == V4L2_QUANTIZATION_DEFAULT) {
        quantization = V4L2_MAP_QUANTIZATION_DEFAULT(false, colorspace, encoding);
    }
    YCbCrColorimetry result;
    const bool bt601Family = encoding == V4L2_YCBCR_ENC_601 || encoding == V4L2_YCBCR_ENC_XV601;
    result.matrix = bt601Family ? YCbCrMatrix::Bt601 : YCbCrMatrix::Bt709;
    // GREY carries no matrix; its range still decides how Y expands.
    result.fullRange = quantization == V4L2_QUANTIZATION_FULL_RANGE;
    return result;
}

std::vector<uint32_t> enumeratePixelFormats(const std::string& device, int fd)
{
    std::vector<uint32_t> formats;
    for (uint32_t index = 0;; ++index) {
        v4l2_fmtdesc description{};
        description.index = index;
        description.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
        const int error = v4l2Ioctl(fd, VIDIOC_ENUM_FMT, &description);
        if (error == EINVAL) {
            break; // the end of the list
        }
        if (error != 0) {
            throwDeviceError(device, "VIDIOC_ENUM_FMT", error);
        }
        if (formats.size() == kMaxV4l2Formats) {
            throw RuntimeError(device + ": VIDIOC_ENUM_FMT lists more than " + std::to_string(kMaxV4l2Formats) +
                               " formats; the driver is broken");
        }
        formats.push_back(description.pixelformat);
    }
    return formats;
}

std::vector<FrameSize> enumerateFrameSizes(const std::string& device, int fd, uint32_t pixelFormat, FrameSize requested)
{
    std::vector<FrameSize> sizes;
    for (uint32_t index = 0;; ++index) {
        v4l2_frmsizeenum size{};
        size.index = index;
        size.pixel_format = pixelFormat;
        const int error = v4l2Ioctl(fd, VIDIOC_ENUM_FRAMESIZES, &size);
        if (error == EINVAL || error == ENOTTY) {
            break; // the end of the list, or a driver that does not enumerate sizes
        }
        if (error != 0) {
            throwDeviceError(device, "VIDIOC_ENUM_FRAMESIZES", error);
        }
        if (sizes.size() == kMaxV4l2FrameSizes) {
            throw RuntimeError(device + ": VIDIOC_ENUM_FRAMESIZES lists more than " +
                               std::to_string(kMaxV4l2FrameSizes) + " sizes; the driver is broken");
        }
        if (size.type == V4L2_FRMSIZE_TYPE_DISCRETE) {
            sizes.push_back({size.discrete.width, size.discrete.height});
            continue;
        }
        // Stepwise or continuous: the request clamped into the range, snapped to the step.
        const auto& range = size.stepwise;
        if (range.min_width > range.max_width || range.min_height > range.max_height) {
            // std::clamp below requires min <= max (the fuzz target's driver broke it).
            throw RuntimeError(device + ": VIDIOC_ENUM_FRAMESIZES gives a size range whose minimum exceeds its "
                                        "maximum; the driver is broken");
        }
        const auto snap = [](uint32_t value, uint32_t low, uint32_t high, uint32_t step) {
            const uint32_t clamped = std::clamp(value, low, high);
            return step > 1 ? low + (clamped - low) / step * step : clamped;
        };
        sizes.push_back({snap(requested.width, range.min_width, range.max_width, range.step_width),
                         snap(requested.height, range.min_height, range.max_height, range.step_height)});
        break;
    }
    if (sizes.empty()) {
        sizes.push_back(requested); // let S_FMT adjust it
    }
    return sizes;
}

} // namespace lumar
