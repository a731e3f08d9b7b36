// How a libcamera stream's buffers become lumar frames: the pixel formats lumar converts
// (NV12, then YUYV, then packed RGB for pipelines without a YCbCr viewfinder format, such as
// vimc), the YCbCr matrix and range a stream's colour space implies, and the conversion of one
// mapped buffer to sRGB plus luma (YCbCr with the V4L2 backend's converter).
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

// The formats lumar converts, best first: NV12 (4:2:0, what ISPs produce natively), YUYV,
// then packed 8-bit RGB: BGR888, RGB888, XBGR8888, XRGB8888. The YCbCr ones come first
// because only they can be converted on the GPU or lent; BGR888 leads the RGB ones because its
// bytes are already lumar's R, G, B order and it is vimc's default (its only working format on
// kernels before 5.7), and the 3-byte formats move a quarter less memory than the 4-byte ones.
const std::vector<libcamera::PixelFormat>& convertibleLibcameraFormats();
bool isConvertibleLibcameraFormat(const libcamera::PixelFormat& format);
// Whether `format` is one of the packed RGB formats above. libcamera names them as DRM does,
// by the order in a little-endian word, so the bytes in memory run the other way round:
// RGB888 is B, G, R; BGR888 is R, G, B; XRGB8888 is B, G, R, X; XBGR8888 is R, G, B, X.
// They are always converted on the CPU: never kept as planes for the GPU, never lent.
bool isPackedRgbLibcameraFormat(const libcamera::PixelFormat& format);
// "NV12, YUYV, BGR888, RGB888, XBGR8888, XRGB8888": the formats lumar converts, for messages.
std::string convertibleLibcameraFormatNames();
// Why none of `offered` can be read (what chooseLibcameraFormat returned none for), as the
// rest of a sentence after "camera <id> ": "has no viewfinder format lumar converts (offers
// MJPEG; lumar converts NV12, ...)" or "does not offer camera.format YUYV (offers ...)".
std::string noConvertibleFormatReason(const std::vector<libcamera::PixelFormat>& offered,
                                      const libcamera::PixelFormat& required);

// The format a config's camera.format names for libcamera: "nv12", "yuyv", or an invalid
// (default) PixelFormat for "auto" (which picks packed RGB when a camera offers nothing
// else). The names are shared with the V4L2 backend, which has no RGB format names, so RGB
// has none here either. Throws InputError for the formats only the V4L2 backend reads
// ("mjpeg", "grey") and for any other name.
libcamera::PixelFormat libcameraFormatFromName(const std::string& name);

// The best of `offered` that lumar converts; an invalid (default) PixelFormat when none is.
// A valid `required` format (the config named it) is chosen when offered, else none is.
libcamera::PixelFormat chooseLibcameraFormat(const std::vector<libcamera::PixelFormat>& offered,
                                             const libcamera::PixelFormat& required = {});

// The matrix and range of a stream's colour space (meaningful for YCbCr formats only: a
// packed RGB stream has no matrix, and its converter is not used). Without one (the pipeline
// did not say), BT.601 limited range, what sensor ISPs and UVC cameras send unless told
// otherwise. BT.2020 falls back to BT.709, the closer of the two matrices lumar converts.
YCbCrColorimetry colorimetryOfColorSpace(const std::optional<libcamera::ColorSpace>& colorSpace);

// One configured stream's image layout.
struct LibcameraLayout {
    libcamera::PixelFormat format;
    int width = 0;
    int height = 0;
    size_t stride = 0; // bytes per row of the first plane (and of NV12's interleaved chroma)
};

// The bytes a whole image of `layout` occupies (both NV12 planes together; RGB: stride x height).
size_t imageBytes(const LibcameraLayout& layout);

// Empty when `mapping` holds a whole image of `layout` (NV12 as one plane or two); else why
// not, in a few words.
std::string checkMappedImage(const DmabufMapping& mapping, const LibcameraLayout& layout);

// Converts one mapped buffer (checked with checkMappedImage) into the frame's rgb and luma.
// `converter` is used for the YCbCr formats only; packed RGB is reordered to R, G, B and its
// luma is BT.601 (as the fake and image sources compute it).
void convertLibcameraImage(const DmabufMapping& mapping, const LibcameraLayout& layout, const YCbCrConverter& converter,
                           Frame& frame);

// The same buffer kept in its YCbCr layout for the renderer's GPU conversion (like the V4L2
// source with camera.convert = "gpu"): the planes copied tightly packed into frame.ycbcr with
// the converter's matrix and range, and the tracker's luma filled. A packed RGB buffer has no
// YCbCr planes to keep: it is converted as convertLibcameraImage does (frame.ycbcr left empty).
void keepLibcameraPlanes(const DmabufMapping& mapping, const LibcameraLayout& layout, const YCbCrConverter& converter,
                         Frame& frame);

} // namespace lumar
