#include "capture/libcamera/libcamera_frame.h"

#include <algorithm>
#include <cstring>

#include <libcamera/formats.h>

#include "core/error.h"

namespace lumar {
namespace {

// NV12's chroma plane: where it starts and how long it may be, for one plane or two.
struct ChromaPlane {
    const uint8_t* data = nullptr;
    size_t length = 0;
};

ChromaPlane nv12Chroma(const DmabufMapping& mapping, const LibcameraLayout& layout)
{
    if (mapping.planeCount() >= 2) {
        return {mapping.plane(1), mapping.planeLength(1)};
    }
    const size_t lumaBytes = layout.stride * size_t(layout.height);
    const size_t length = mapping.planeLength(0) > lumaBytes ? mapping.planeLength(0) - lumaBytes : 0;
    return {mapping.plane(0) + lumaBytes, length};
}

} // namespace

const std::vector<libcamera::PixelFormat>& convertibleLibcameraFormats()
{
    static const std::vector<libcamera::PixelFormat> formats{libcamera::formats::NV12, libcamera::formats::YUYV};
    return formats;
}

bool isConvertibleLibcameraFormat(const libcamera::PixelFormat& format)
{
    const auto& formats = convertibleLibcameraFormats();
    return std::find(formats.begin(), formats.end(), format) != formats.end();
}

libcamera::PixelFormat libcameraFormatFromName(const std::string& name)
{
    if (name == "auto")
        return {};
    if (name == "nv12")
        return libcamera::formats::NV12;
    if (name == "yuyv")
        return libcamera::formats::YUYV;
    throw InputError("camera.format: '" + name +
                     "' is not a format lumar reads from libcamera cameras (expected auto, nv12 or yuyv)");
}

libcamera::PixelFormat chooseLibcameraFormat(const std::vector<libcamera::PixelFormat>& offered,
                                             const libcamera::PixelFormat& required)
{
    if (required.isValid()) {
        return std::find(offered.begin(), offered.end(), required) != offered.end() ? required
                                                                                    : libcamera::PixelFormat{};
    }
    for (const libcamera::PixelFormat& format : convertibleLibcameraFormats()) {
        if (std::find(offered.begin(), offered.end(), format) != offered.end()) {
            return format;
        }
    }
    return {};
}

YCbCrColorimetry colorimetryOfColorSpace(const std::optional<libcamera::ColorSpace>& colorSpace)
{
    YCbCrColorimetry colorimetry;
    if (!colorSpace) {
        return colorimetry;
    }
    using Encoding = libcamera::ColorSpace::YcbcrEncoding;
    colorimetry.matrix = colorSpace->ycbcrEncoding == Encoding::Rec709 || colorSpace->ycbcrEncoding == Encoding::Rec2020
                             ? YCbCrMatrix::Bt709
                             : YCbCrMatrix::Bt601;
    colorimetry.fullRange = colorSpace->range == libcamera::ColorSpace::Range::Full;
    return colorimetry;
}

size_t imageBytes(const LibcameraLayout& layout)
{
    const size_t lumaBytes = layout.stride * size_t(layout.height);
    return layout.format == libcamera::formats::NV12 ? lumaBytes + lumaBytes / 2 : lumaBytes;
}

std::string checkMappedImage(const DmabufMapping& mapping, const LibcameraLayout& layout)
{
    if (!isConvertibleLibcameraFormat(layout.format)) {
        return "pixel format " + layout.format.toString() + " is not one lumar converts";
    }
    const bool nv12 = layout.format == libcamera::formats::NV12;
    const size_t bytesPerPixel = nv12 ? 1 : 2;
    if (layout.width <= 0 || layout.height <= 0 || layout.width % 2 != 0 || (nv12 && layout.height % 2 != 0) ||
        layout.stride < size_t(layout.width) * bytesPerPixel) {
        return "unusable layout " + std::to_string(layout.width) + "x" + std::to_string(layout.height) + ", stride " +
               std::to_string(layout.stride);
    }
    if (mapping.planeCount() == 0) {
        return "the buffer has no planes";
    }
    const size_t lumaBytes = layout.stride * size_t(layout.height);
    if (mapping.planeLength(0) < lumaBytes) {
        return "plane 0 holds " + std::to_string(mapping.planeLength(0)) + " bytes, the image needs " +
               std::to_string(lumaBytes);
    }
    if (nv12 && nv12Chroma(mapping, layout).length < lumaBytes / 2) {
        return "the chroma plane holds " + std::to_string(nv12Chroma(mapping, layout).length) + " bytes, it needs " +
               std::to_string(lumaBytes / 2);
    }
    return {};
}

void convertLibcameraImage(const DmabufMapping& mapping, const LibcameraLayout& layout, const YCbCrConverter& converter,
                           Frame& frame)
{
    if (layout.format == libcamera::formats::NV12) {
        converter.convertNv12(mapping.plane(0), layout.stride, nv12Chroma(mapping, layout).data, layout.stride,
                              layout.width, layout.height, frame.rgb, frame.luma);
    } else {
        converter.convertYuyv(mapping.plane(0), layout.stride, layout.width, layout.height, frame.rgb, frame.luma);
    }
}

void keepLibcameraPlanes(const DmabufMapping& mapping, const LibcameraLayout& layout, const YCbCrConverter& converter,
                         Frame& frame)
{
    YCbCrImage& raw = frame.ycbcr;
    raw.width = layout.width;
    raw.height = layout.height;
    raw.colorimetry = converter.colorimetry();
    const size_t width = size_t(layout.width);
    if (layout.format == libcamera::formats::NV12) {
        raw.layout = YCbCrLayout::Nv12;
        copyPlaneRows(mapping.plane(0), layout.stride, width, layout.height, raw.plane0);
        copyPlaneRows(nv12Chroma(mapping, layout).data, layout.stride, width, layout.height / 2, raw.plane1);
        raw.stride0 = raw.stride1 = width;
        converter.convertLuma(mapping.plane(0), layout.stride, 1, layout.width, layout.height, frame.luma);
    } else {
        raw.layout = YCbCrLayout::Yuyv;
        copyPlaneRows(mapping.plane(0), layout.stride, width * 2, layout.height, raw.plane0);
        raw.plane1.clear();
        raw.stride0 = width * 2;
        raw.stride1 = 0;
        converter.convertLuma(mapping.plane(0), layout.stride, 2, layout.width, layout.height, frame.luma);
    }
}

} // namespace lumar
