// A Motion-JPEG frame as a UVC camera sends it, through the decoder V4l2Source uses
// (capture/v4l2/mjpeg_decoder.h). The negotiated size is the one the JPEG declares (a
// camera's frames match the format it agreed to), so the decode itself is reached; a second
// call with another size takes the mismatch path. One decoder for every input, as a stream
// keeps one for all its frames: state left behind by a bad frame must not hurt the next.
#include <memory>
#include <string>

#include <turbojpeg.h>

#include "capture/v4l2/mjpeg_decoder.h"
#include "core/image.h"
#include "fuzz_support.h"

namespace {

// What the tests decode at most: a 2048 x 2048 frame (the format check allows up to 8192 a
// side; the decoder's cost grows with the pixels, not with what is wrong in them).
constexpr long kMaxPixels = 2048L * 2048L;

} // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size)
{
    (void)lumar::fuzz::scratchDir(); // logs off
    static lumar::MjpegDecoder decoder;
    static const std::unique_ptr<void, int (*)(tjhandle)> header(tjInitDecompress(), tjDestroy);
    int width = 64, height = 48, subsampling = 0, colourspace = 0;
    if (size > 0 && tjDecompressHeader3(header.get(), data, static_cast<unsigned long>(size), &width, &height,
                                        &subsampling, &colourspace) != 0) {
        width = 64;
        height = 48;
    }
    if (width <= 0 || height <= 0 || long(width) * long(height) > kMaxPixels)
        return 0;
    lumar::Image8 rgb, luma;
    std::string error;
    if (decoder.decode(data, size, width, height, rgb, luma, error)) {
        // A decoded frame fills both images at the negotiated size.
        if (rgb.width != width || rgb.height != height || luma.width != width || luma.height != height)
            __builtin_trap();
    } else if (error.empty()) {
        __builtin_trap(); // a refusal always says why (the log line names it)
    }
    (void)decoder.decode(data, size, width + 2, height, rgb, luma, error);
    return 0;
}
