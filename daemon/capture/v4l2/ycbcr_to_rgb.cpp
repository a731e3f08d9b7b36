#include "capture/v4l2/ycbcr_to_rgb.h"

#include <algorithm>
#include <cmath>
#include <cstring>

namespace lumar {
namespace {

constexpr double kFixedOne = 65536.0;

int32_t toFixed(double v)
{
    return int32_t(std::lround(v * kFixedOne));
}

uint8_t fixedToByte(int32_t v)
{
    // +0.5 in 16.16 rounds to nearest; the clamp absorbs footroom/headroom excursions.
    return uint8_t(std::clamp((v + 32768) >> 16, 0, 255));
}

} // namespace

YCbCrConverter::YCbCrConverter(YCbCrColorimetry colorimetry) : colorimetry_(colorimetry)
{
    // Kr and Kb of the two matrices (ITU-R BT.601-7 and BT.709-6).
    const double kr = colorimetry.matrix == YCbCrMatrix::Bt709 ? 0.2126 : 0.299;
    const double kb = colorimetry.matrix == YCbCrMatrix::Bt709 ? 0.0722 : 0.114;
    const double kg = 1.0 - kr - kb;
    const double yOffset = colorimetry.fullRange ? 0.0 : 16.0;
    const double yScale = colorimetry.fullRange ? 1.0 : 255.0 / 219.0;
    const double cScale = colorimetry.fullRange ? 1.0 : 255.0 / 224.0;
    for (int v = 0; v < 256; ++v) {
        const double c = (v - 128) * cScale;
        const auto i = size_t(v);
        yTerm_[i] = toFixed((v - yOffset) * yScale);
        luma_[i] = fixedToByte(yTerm_[i]);
        crToRed_[i] = toFixed(2.0 * (1.0 - kr) * c);
        cbToBlue_[i] = toFixed(2.0 * (1.0 - kb) * c);
        cbToGreen_[i] = toFixed(2.0 * (1.0 - kb) * kb / kg * c);
        crToGreen_[i] = toFixed(2.0 * (1.0 - kr) * kr / kg * c);
    }
}

void YCbCrConverter::writePixel(uint8_t yValue, int32_t redChroma, int32_t greenChroma, int32_t blueChroma,
                                uint8_t* rgbOut, uint8_t* lumaOut) const
{
    const int32_t y = yTerm_[yValue];
    rgbOut[0] = fixedToByte(y + redChroma);
    rgbOut[1] = fixedToByte(y - greenChroma);
    rgbOut[2] = fixedToByte(y + blueChroma);
    *lumaOut = luma_[yValue];
}

void YCbCrConverter::convertYuyv(const uint8_t* data, size_t stride, int width, int height, Image8& rgb,
                                 Image8& luma) const
{
    rgb.reshape(width, height, 3);
    luma.reshape(width, height, 1);
    for (int row = 0; row < height; ++row) {
        const uint8_t* in = data + size_t(row) * stride;
        uint8_t* out = rgb.row(row);
        uint8_t* lumaOut = luma.row(row);
        for (int x = 0; x + 1 < width; x += 2, in += 4, out += 6, lumaOut += 2) {
            const int32_t red = crToRed_[in[3]];
            const int32_t green = cbToGreen_[in[1]] + crToGreen_[in[3]];
            const int32_t blue = cbToBlue_[in[1]];
            writePixel(in[0], red, green, blue, out, lumaOut);
            writePixel(in[2], red, green, blue, out + 3, lumaOut + 1);
        }
    }
}

void YCbCrConverter::convertNv12(const uint8_t* yPlane, size_t yStride, const uint8_t* uvPlane, size_t uvStride,
                                 int width, int height, Image8& rgb, Image8& luma) const
{
    rgb.reshape(width, height, 3);
    luma.reshape(width, height, 1);
    for (int row = 0; row < height; ++row) {
        const uint8_t* yIn = yPlane + size_t(row) * yStride;
        const uint8_t* uvIn = uvPlane + size_t(row / 2) * uvStride;
        uint8_t* out = rgb.row(row);
        uint8_t* lumaOut = luma.row(row);
        for (int x = 0; x + 1 < width; x += 2, yIn += 2, uvIn += 2, out += 6, lumaOut += 2) {
            const int32_t red = crToRed_[uvIn[1]];
            const int32_t green = cbToGreen_[uvIn[0]] + crToGreen_[uvIn[1]];
            const int32_t blue = cbToBlue_[uvIn[0]];
            writePixel(yIn[0], red, green, blue, out, lumaOut);
            writePixel(yIn[1], red, green, blue, out + 3, lumaOut + 1);
        }
    }
}

void YCbCrConverter::convertLuma(const uint8_t* data, size_t stride, size_t step, int width, int height,
                                 Image8& luma) const
{
    luma.reshape(width, height, 1);
    for (int row = 0; row < height; ++row) {
        const uint8_t* in = data + size_t(row) * stride;
        uint8_t* out = luma.row(row);
        if (colorimetry_.fullRange && step == 1) {
            std::memcpy(out, in, size_t(width)); // full range: Y is the luma
        } else if (colorimetry_.fullRange) {
            for (int x = 0; x < width; ++x)
                out[x] = in[size_t(x) * step];
        } else {
            for (int x = 0; x < width; ++x)
                out[x] = luma_[in[size_t(x) * step]];
        }
    }
}

void YCbCrConverter::convertGrey(const uint8_t* data, size_t stride, int width, int height, Image8& rgb,
                                 Image8& luma) const
{
    rgb.reshape(width, height, 3);
    luma.reshape(width, height, 1);
    for (int row = 0; row < height; ++row) {
        const uint8_t* in = data + size_t(row) * stride;
        uint8_t* out = rgb.row(row);
        uint8_t* lumaOut = luma.row(row);
        if (colorimetry_.fullRange)
            std::memcpy(lumaOut, in, size_t(width));
        else
            for (int x = 0; x < width; ++x)
                lumaOut[x] = luma_[in[x]];
        for (int x = 0; x < width; ++x, out += 3)
            out[0] = out[1] = out[2] = lumaOut[x];
    }
}

} // namespace lumar
