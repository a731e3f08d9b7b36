// How a libcamera stream's buffers become lumar frames: the pixel formats lumar converts
// (NV12, then YUYV), the YCbCr matrix and range a stream's colour space implies, and the
// conversion of one mapped buffer to sRGB plus luma with the V4L2 backend's converter.
#pragma once

#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include <libcamera/color_space.h>
#include <libcamera/pixel_format.h>

#include "capture/libcamera/dmabuf_mapping.h"
#include "capture/v4l2/ycbcr_to_rgb.h"
#include "core/frame.h"

namespace lumar {

// The formats lumar converts, best first: NV12 (4:2:0, what ISPs produce natively), YUYV.
const std::vector<libcamera::PixelFormat>& convertibleLibcameraFormats();
bool isConvertibleLibcameraFormat(const libcamera::PixelFormat& format);

// The format a config's camera.format names for libcamera: "nv12", "yuyv", or an invalid
// (default) PixelFormat for "auto". Throws InputError for the formats only the V4L2 backend
// reads ("mjpeg", "grey") and for any other name.
libcamera::PixelFormat libcameraFormatFromName(const std::string& name);

// The best of `offered` that lumar converts; an invalid (default) PixelFormat when none is.
// A valid `required` format (the config named it) is chosen when offered, else none is.
libcamera::PixelFormat chooseLibcameraFormat(const std::vector<libcamera::PixelFormat>& offered,
                                             const libcamera::PixelFormat& required = {});

// The matrix and range of a stream's colour space. Without one (the pipeline did not say),
// BT.601 limited range, what sensor ISPs and UVC cameras send unless told otherwise. BT.2020
// falls back to BT.709, the closer of the two matrices lumar converts.
YCbCrColorimetry colorimetryOfColorSpace(const std::optional<libcamera::ColorSpace>& colorSpace);

// One configured stream's image layout.
struct LibcameraLayout {
    libcamera::PixelFormat format;
    int width = 0;
    int height = 0;
    size_t stride = 0; // bytes per row of the first plane (and of NV12's interleaved chroma)
};

// The bytes a whole image of `layout` occupies (both NV12 planes together).
size_t imageBytes(const LibcameraLayout& layout);

// Empty when `mapping` holds a whole image of `layout` (NV12 as one plane or two); else why
// not, in a few words.
std::string checkMappedImage(const DmabufMapping& mapping, const LibcameraLayout& layout);

// Converts one mapped buffer (checked with checkMappedImage) into the frame's rgb and luma.
void convertLibcameraImage(const DmabufMapping& mapping, const LibcameraLayout& layout, const YCbCrConverter& converter,
                           Frame& frame);

// The same buffer kept in its YCbCr layout for the renderer's GPU conversion (like the V4L2
// source with camera.convert = "gpu"): the planes copied tightly packed into frame.ycbcr with
// the converter's matrix and range, and the tracker's luma filled.
void keepLibcameraPlanes(const DmabufMapping& mapping, const LibcameraLayout& layout, const YCbCrConverter& converter,
                         Frame& frame);

} // namespace lumar
