// Motion-JPEG frames (V4L2_PIX_FMT_MJPEG, what most UVC webcams send at 720p and above)
// decoded with libturbojpeg into the two images a frame carries: the JPEG's own Y plane
// becomes the tracker's luma unchanged (JFIF's Y is full-range BT.601, as the luma of the
// other formats), and libturbojpeg's SIMD colour conversion makes the sRGB image from the
// decoded planes, so the entropy decoding runs once.
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "core/image.h"

namespace lumar {

class MjpegDecoder {
public:
    // Throws RuntimeError when libturbojpeg cannot create a decompressor.
    MjpegDecoder();

    // Decodes one frame that must be `width` x `height`. Returns false (and leaves a reason in
    // `error`) for data that is not a complete JPEG of that size; `rgb` and `luma` may then hold
    // a partial picture. Never throws.
    bool decode(const uint8_t* jpeg, size_t size, int width, int height, Image8& rgb, Image8& luma, std::string& error);

private:
    struct HandleDeleter {
        void operator()(void* handle) const;
    };
    std::unique_ptr<void, HandleDeleter> handle_; // a tjhandle
    std::vector<uint8_t> chroma_;                 // the Cb and Cr planes between the two steps
    std::vector<uint8_t> lumaScratch_;            // the Y plane when its padding differs from the frame
};

} // namespace lumar
