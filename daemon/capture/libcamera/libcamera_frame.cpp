#include "capture/libcamera/libcamera_frame.h"

#include <algorithm>
#include <array>
#include <cstring>

#include <libcamera/formats.h>

#include "capture/colour_conversion.h"
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

// One packed layout's rows into R, G, B and luma. The channel offsets (bytes within a pixel)
// are template arguments so the inner loop is a fixed shuffle per pixel.
template <size_t BytesPerPixel, size_t Red, size_t Green, size_t Blue>
void convertPackedRgb(const uint8_t* data, size_t stride, int width, int height, Image8& rgb, Image8& luma)
{
    rgb.reshape(width, height, 3);
    luma.reshape(width, height, 1);
    for (int y = 0; y < height; ++y) {
        const uint8_t* in = data + stride * size_t(y); // the row's padding is skipped
        uint8_t* rgbOut = rgb.row(y);
        uint8_t* lumaOut = luma.row(y);
        for (int x = 0; x < width; ++x, in += BytesPerPixel, rgbOut += 3) {
            rgbOut[0] = in[Red];
            rgbOut[1] = in[Green];
            rgbOut[2] = in[Blue];
            // The tracker needs a grey image with the markers' black/white contrast, not a
            // colorimetrically exact one: BT.601 weights on the sRGB-encoded values (the
            // fake and image-folder sources' luma too) give what a YCbCr camera's Y carries,
            // so detection behaves alike whatever format the camera sends.
            lumaOut[x] = bt601Luma(in[Red], in[Green], in[Blue]);
        }
    }
}

// A packed RGB format: its size per pixel and its conversion (see isPackedRgbLibcameraFormat
// for the DRM naming that puts the bytes in the reverse order of the name).
struct PackedRgb {
    libcamera::PixelFormat format;
    size_t bytesPerPixel;
    void (*convert)(const uint8_t* data, size_t stride, int width, int height, Image8& rgb, Image8& luma);
};

// In the order lumar prefers them (see convertibleLibcameraFormats).
const std::array<PackedRgb, 4>& packedRgbFormats()
{
    static const std::array<PackedRgb, 4> formats{{
        {libcamera::formats::BGR888, 3, &convertPackedRgb<3, 0, 1, 2>},   // R, G, B
        {libcamera::formats::RGB888, 3, &convertPackedRgb<3, 2, 1, 0>},   // B, G, R
        {libcamera::formats::XBGR8888, 4, &convertPackedRgb<4, 0, 1, 2>}, // R, G, B, X
        {libcamera::formats::XRGB8888, 4, &convertPackedRgb<4, 2, 1, 0>}, // B, G, R, X
    }};
    return formats;
}

const PackedRgb* packedRgbOf(const libcamera::PixelFormat& format)
{
    for (const PackedRgb& packed : packedRgbFormats()) {
        if (packed.format == format)
            return &packed;
    }
    return nullptr;
}

// "NV12, YUYV, …"
std::string formatNames(const std::vector<libcamera::PixelFormat>& formats)
{
    std::string names;
    for (const libcamera::PixelFormat& format : formats)
        names += (names.empty() ? "" : ", ") + format.toString();
    return names;
}

} // namespace

const std::vector<libcamera::PixelFormat>& convertibleLibcameraFormats()
{
    static const std::vector<libcamera::PixelFormat> formats = [] {
        std::vector<libcamera::PixelFormat> all{libcamera::formats::NV12, libcamera::formats::YUYV};
        for (const PackedRgb& packed : packedRgbFormats())
            all.push_back(packed.format);
        return all;
    }();
    return formats;
}

bool isPackedRgbLibcameraFormat(const libcamera::PixelFormat& format)
{
    return packedRgbOf(format) != nullptr;
}

std::string convertibleLibcameraFormatNames()
{
    return formatNames(convertibleLibcameraFormats());
}

std::string noConvertibleFormatReason(const std::vector<libcamera::PixelFormat>& offered,
                                      const libcamera::PixelFormat& required)
{
    const std::string offeredNames = formatNames(offered);
    return (required.isValid() ? "does not offer camera.format " + required.toString()
                               : std::string("has no viewfinder format lumar converts")) +
           " (offers " + (offeredNames.empty() ? "none" : offeredNames) + "; lumar converts " +
           convertibleLibcameraFormatNames() + ")";
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
    const PackedRgb* packed = packedRgbOf(layout.format);
    const size_t bytesPerPixel = packed ? packed->bytesPerPixel : nv12 ? 1 : 2;
    // Chroma subsampling needs even widths (and heights for NV12); packed RGB has none.
    const bool oddAllowed = packed != nullptr;
    if (layout.width <= 0 || layout.height <= 0 || (!oddAllowed && layout.width % 2 != 0) ||
        (nv12 && layout.height % 2 != 0) || layout.stride < size_t(layout.width) * bytesPerPixel) {
        return "unusable layout " + std::to_string(layout.width) + "x" + std::to_string(layout.height) + ", stride " +
               std::to_string(layout.stride);
    }
    if (mapping.planeCount() == 0) {
        return "the buffer has no planes";
    }
    // The whole image: a packed RGB image is one plane of stride x height, like YUYV.
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
    if (const PackedRgb* packed = packedRgbOf(layout.format)) {
        packed->convert(mapping.plane(0), layout.stride, layout.width, layout.height, frame.rgb, frame.luma);
    } else if (layout.format == libcamera::formats::NV12) {
        converter.convertNv12(mapping.plane(0), layout.stride, nv12Chroma(mapping, layout).data, layout.stride,
                              layout.width, layout.height, frame.rgb, frame.luma);
    } else {
        converter.convertYuyv(mapping.plane(0), layout.stride, layout.width, layout.height, frame.rgb, frame.luma);
    }
}

void keepLibcameraPlanes(const DmabufMapping& mapping, const LibcameraLayout& layout, const YCbCrConverter& converter,
                         Frame& frame)
{
    if (isPackedRgbLibcameraFormat(layout.format)) {
        // Nothing for the GPU's YCbCr conversion to take: the frame is its RGB image.
        frame.ycbcr.layout = YCbCrLayout::None;
        convertLibcameraImage(mapping, layout, converter, frame);
        return;
    }
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
