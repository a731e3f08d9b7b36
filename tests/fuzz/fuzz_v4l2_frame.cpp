// The V4L2 frame path with a driver's answers taken from the input, as a broken or hostile
// driver (or a USB device lying through uvcvideo) might give them: the negotiated format
// (pixel format, sizes, bytes per line, image size, colorimetry) checked by frameLayoutOf(),
// a dequeued buffer (flags, bytesused, the mapping's length) checked by bufferDefect(), and the
// buffer's bytes converted by convertV4l2Frame(): the functions V4l2Source calls
// (capture/v4l2/v4l2_frame_layout.h). ASan sees every read past the buffer a wrong size or
// stride would cause.
//
// Input: a 30-byte header, little-endian, then the buffer's bytes (repeated to fill it):
//   u8 format (low 2 bits: NV12, YUYV, MJPEG, GREY; bit 2: the driver answers another format)
//   u32 width, u32 height, u32 bytesperline, u32 sizeimage
//   u8 colorspace, u8 ycbcr_enc, u8 quantization
//   u8 buffer flags (bit 0: V4L2_BUF_FLAG_ERROR; bit 1: keep NV12/YUYV planes raw)
//   u32 bytesused, u32 mapping length
#include <algorithm>
#include <cstring>
#include <vector>

#include "capture/v4l2/v4l2_format.h"
#include "capture/v4l2/v4l2_frame_layout.h"
#include "core/error.h"
#include "core/frame.h"
#include "fuzz_support.h"

namespace {

constexpr size_t kHeaderBytes = 30;
// Mappings larger than this are skipped: their checks ran, and converting them only costs
// time (a real mapping's size is what the driver says, up to kMaxV4l2ImageBytes).
constexpr size_t kMaxMappedBytes = size_t(4) << 20;

uint32_t readU32(const uint8_t* p)
{
    return uint32_t(p[0]) | uint32_t(p[1]) << 8 | uint32_t(p[2]) << 16 | uint32_t(p[3]) << 24;
}

} // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size)
{
    (void)lumar::fuzz::scratchDir(); // logs off
    if (size < kHeaderBytes)
        return 0;
    static const uint32_t kFormats[] = {V4L2_PIX_FMT_NV12, V4L2_PIX_FMT_YUYV, V4L2_PIX_FMT_MJPEG, V4L2_PIX_FMT_GREY};
    const uint32_t requested = kFormats[data[0] & 3];
    v4l2_pix_format accepted{};
    accepted.pixelformat = (data[0] & 4) ? kFormats[(data[0] + 1) & 3] : requested;
    accepted.width = readU32(data + 1);
    accepted.height = readU32(data + 5);
    accepted.bytesperline = readU32(data + 9);
    accepted.sizeimage = readU32(data + 13);
    accepted.colorspace = data[17];
    accepted.ycbcr_enc = data[18];
    accepted.quantization = data[19];
    const uint32_t flags = (data[20] & 1) ? V4L2_BUF_FLAG_ERROR : 0;
    const bool keepRaw = (data[20] & 2) != 0;
    const size_t bytesUsed = readU32(data + 21);
    const size_t length = readU32(data + 25);
    // data[29]: reserved (keeps the payload's start fixed if the header grows a field).
    const uint8_t* payload = data + kHeaderBytes;
    const size_t payloadSize = size - kHeaderBytes;

    lumar::V4l2FrameLayout layout;
    try {
        layout = lumar::frameLayoutOf("/dev/fuzz", accepted, requested);
    } catch (const lumar::RuntimeError&) {
        return 0; // the stream is refused before any buffer is mapped
    }
    // What the refusal guarantees: every row the converters read lies inside the image size.
    if (layout.width <= 0 || layout.height <= 0 || (layout.imageSize > 0 && layout.imageSize > accepted.sizeimage))
        __builtin_trap();
    // mapBuffers() refuses a mapping shorter than the image.
    if (length < layout.imageSize || length > kMaxMappedBytes)
        return 0;
    if (!lumar::bufferDefect(layout, flags, bytesUsed, length).empty())
        return 0;

    // The mapping: exactly `length` bytes (ASan's redzone right behind), the payload repeated.
    std::vector<uint8_t> mapping(length);
    for (size_t i = 0; i < length && payloadSize > 0; i += payloadSize)
        std::memcpy(mapping.data() + i, payload, std::min(payloadSize, length - i));
    const lumar::YCbCrConverter converter(lumar::colorimetryOf(accepted));
    static lumar::MjpegDecoder decoder;
    lumar::Frame frame;
    std::string error;
    const bool converted =
        lumar::convertV4l2Frame(layout, converter, &decoder, keepRaw, mapping.data(), bytesUsed, frame, error);
    if (converted &&
        !(keepRaw && layout.pixelFormat != V4L2_PIX_FMT_MJPEG && layout.pixelFormat != V4L2_PIX_FMT_GREY)) {
        if (frame.rgb.width != layout.width || frame.rgb.height != layout.height)
            __builtin_trap();
    }
    if (converted && (frame.luma.width != layout.width || frame.luma.height != layout.height))
        __builtin_trap();
    return 0;
}
