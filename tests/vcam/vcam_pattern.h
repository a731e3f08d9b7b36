// What the virtual camera films: 75 % colour bars over the top three quarters and, below, a
// white block on black that moves 8 px per frame, so a test can tell which frame it holds.
// Encoded into the device's pixel format with the configured matrix and range.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>

namespace lumar::vcam {

struct Rgb {
    uint8_t r = 0;
    uint8_t g = 0;
    uint8_t b = 0;
};

// White, yellow, cyan, green, magenta, red, blue, black at 75 % (191 of 255).
const std::array<Rgb, 8>& colourBars();
inline constexpr int kBlockWidth = 32;
// The block's left edge in frame `frameIndex` of a picture `width` wide (always even).
int blockLeft(int64_t frameIndex, int width);
// The first row of the moving-block band (always even).
int blockBandTop(int height);

struct PatternFormat {
    uint32_t pixelFormat = 0; // V4L2_PIX_FMT_YUYV, _NV12 or _GREY
    int width = 0;
    int height = 0;
    size_t bytesPerLine = 0;
    bool bt709 = false;
    bool fullRange = false;
};

// Writes frame `frameIndex` into `out`, which holds the format's full image size (YUYV, NV12
// or GREY).
void drawPattern(const PatternFormat& format, int64_t frameIndex, uint8_t* out);

// The same picture as 8-bit RGB, 3 bytes a pixel, rows packed (what the MJPEG encoder takes).
// It depends on the frame only through blockLeft(frameIndex, width).
void drawPatternRgb(int width, int height, int64_t frameIndex, uint8_t* rgb);

} // namespace lumar::vcam
