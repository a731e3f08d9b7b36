#include "core/pixel_pack.h"

#include <bit>
#include <cstring>

namespace lumar {

static_assert(std::endian::native == std::endian::little, "the word masks below assume little-endian bytes");

// Written for the compiler to vectorise: a 4-byte load per pixel (the pixel and the next one's
// first byte, masked) instead of byte moves. Why not libyuv: its byte orders are BGRA-first,
// and one loop does not justify another package on every board.
void expandRgbToRgba(const uint8_t* rgb, uint8_t* rgba, size_t pixels)
{
    if (pixels == 0)
        return;
    // Every pixel but the last can read 4 bytes without leaving the input.
    for (size_t i = 0; i + 1 < pixels; ++i) {
        uint32_t word;
        std::memcpy(&word, rgb + 3 * i, 4);
        word = (word & 0x00ffffffu) | 0xff000000u; // little-endian: byte 3 is alpha
        std::memcpy(rgba + 4 * i, &word, 4);
    }
    const size_t last = pixels - 1;
    rgba[4 * last + 0] = rgb[3 * last + 0];
    rgba[4 * last + 1] = rgb[3 * last + 1];
    rgba[4 * last + 2] = rgb[3 * last + 2];
    rgba[4 * last + 3] = 255;
}

void packRgbaToRgb(const uint8_t* rgba, uint8_t* rgb, size_t pixels)
{
    if (pixels == 0)
        return;
    // Every pixel but the last writes 4 bytes, the fourth overwritten by the next pixel.
    for (size_t i = 0; i + 1 < pixels; ++i)
        std::memcpy(rgb + 3 * i, rgba + 4 * i, 4);
    const size_t last = pixels - 1;
    std::memcpy(rgb + 3 * last, rgba + 4 * last, 3);
}

} // namespace lumar
