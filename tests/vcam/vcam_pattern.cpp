#include "vcam/vcam_pattern.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include <linux/videodev2.h>

namespace lumar::vcam {
namespace {

struct YCbCr {
    uint8_t y = 0;
    uint8_t cb = 0;
    uint8_t cr = 0;
};

uint8_t quantize(double v)
{
    return uint8_t(std::clamp(std::lround(v), 0L, 255L));
}

// The forward transform of ITU-R BT.601 / BT.709 from 8-bit (gamma-encoded) R'G'B'.
YCbCr encode(Rgb colour, bool bt709, bool fullRange)
{
    const double kr = bt709 ? 0.2126 : 0.299;
    const double kb = bt709 ? 0.0722 : 0.114;
    const double r = colour.r / 255.0;
    const double g = colour.g / 255.0;
    const double b = colour.b / 255.0;
    const double y = kr * r + (1.0 - kr - kb) * g + kb * b;
    const double pb = (b - y) / (2.0 * (1.0 - kb));
    const double pr = (r - y) / (2.0 * (1.0 - kr));
    if (fullRange) {
        return {quantize(255.0 * y), quantize(128.0 + 255.0 * pb), quantize(128.0 + 255.0 * pr)};
    }
    return {quantize(16.0 + 219.0 * y), quantize(128.0 + 224.0 * pb), quantize(128.0 + 224.0 * pr)};
}

} // namespace

const std::array<Rgb, 8>& colourBars()
{
    static const std::array<Rgb, 8> bars{{{191, 191, 191},
                                          {191, 191, 0},
                                          {0, 191, 191},
                                          {0, 191, 0},
                                          {191, 0, 191},
                                          {191, 0, 0},
                                          {0, 0, 191},
                                          {0, 0, 0}}};
    return bars;
}

int blockLeft(int64_t frameIndex, int width)
{
    const int64_t travel = std::max(width - kBlockWidth, 2);
    return int((frameIndex * 8) % travel) & ~1;
}

int blockBandTop(int height)
{
    return (height * 3 / 4) & ~1;
}

void drawPattern(const PatternFormat& format, int64_t frameIndex, uint8_t* out)
{
    const int w = format.width;
    const int h = format.height;
    // The two kinds of row, one colour per pixel; bar and block edges fall on even columns
    // (bars are w/8 wide with w a multiple of 16 for every offered size), so 4:2:x chroma
    // pairs never straddle two colours.
    std::vector<YCbCr> barRow(static_cast<size_t>(w));
    std::vector<YCbCr> blockRow(static_cast<size_t>(w));
    const YCbCr white = encode({255, 255, 255}, format.bt709, format.fullRange);
    const YCbCr black = encode({0, 0, 0}, format.bt709, format.fullRange);
    const int left = blockLeft(frameIndex, w);
    for (int x = 0; x < w; ++x) {
        barRow[size_t(x)] = encode(colourBars()[size_t(x * 8 / w)], format.bt709, format.fullRange);
        blockRow[size_t(x)] = (x >= left && x < left + kBlockWidth) ? white : black;
    }
    const int bandTop = blockBandTop(h);
    const auto rowColours = [&](int y) -> const std::vector<YCbCr>& { return y < bandTop ? barRow : blockRow; };

    for (int y = 0; y < h; ++y) {
        const std::vector<YCbCr>& colours = rowColours(y);
        uint8_t* line = out + size_t(y) * format.bytesPerLine;
        if (format.pixelFormat == V4L2_PIX_FMT_YUYV) {
            for (int x = 0; x + 1 < w; x += 2) {
                line[2 * x] = colours[size_t(x)].y;
                line[2 * x + 1] = colours[size_t(x)].cb;
                line[2 * x + 2] = colours[size_t(x + 1)].y;
                line[2 * x + 3] = colours[size_t(x)].cr;
            }
        } else {
            for (int x = 0; x < w; ++x) {
                line[x] = colours[size_t(x)].y;
            }
        }
    }
    if (format.pixelFormat == V4L2_PIX_FMT_NV12) {
        uint8_t* chroma = out + format.bytesPerLine * size_t(h);
        for (int y = 0; y < h / 2; ++y) {
            const std::vector<YCbCr>& colours = rowColours(2 * y);
            uint8_t* line = chroma + size_t(y) * format.bytesPerLine;
            for (int x = 0; x + 1 < w; x += 2) {
                line[x] = colours[size_t(x)].cb;
                line[x + 1] = colours[size_t(x)].cr;
            }
        }
    }
}

void drawPatternRgb(int width, int height, int64_t frameIndex, uint8_t* rgb)
{
    const int left = blockLeft(frameIndex, width);
    const int bandTop = blockBandTop(height);
    for (int y = 0; y < height; ++y) {
        uint8_t* out = rgb + size_t(y) * size_t(width) * 3;
        for (int x = 0; x < width; ++x, out += 3) {
            Rgb colour = colourBars()[size_t(x * 8 / width)];
            if (y >= bandTop) {
                const uint8_t v = (x >= left && x < left + kBlockWidth) ? 255 : 0;
                colour = {v, v, v};
            }
            out[0] = colour.r;
            out[1] = colour.g;
            out[2] = colour.b;
        }
    }
}

} // namespace lumar::vcam
