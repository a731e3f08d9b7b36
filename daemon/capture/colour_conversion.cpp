#include "capture/colour_conversion.h"

#include <algorithm>
#include <cmath>

namespace lumar {
namespace {

uint8_t clampToByte(float v)
{
    return uint8_t(std::clamp(std::lround(v), 0L, 255L));
}

// Chroma samples are centred between the luma samples they cover (JPEG siting); the MPEG-2
// and PAL-DV sitings differ by a quarter chroma sample, invisible at the tracker's scale.
std::vector<YCbCrToRgb::Tap> upsamplingTaps(int fullSize, int subSize)
{
    std::vector<YCbCrToRgb::Tap> taps(static_cast<size_t>(fullSize));
    for (int i = 0; i < fullSize; ++i) {
        const double pos = (i + 0.5) * subSize / fullSize - 0.5;
        const double clamped = std::clamp(pos, 0.0, double(subSize - 1));
        const int lower = int(std::floor(clamped));
        YCbCrToRgb::Tap& tap = taps[size_t(i)];
        tap.lower = lower;
        tap.upper = std::min(lower + 1, subSize - 1);
        tap.upperWeight = float(clamped - lower);
    }
    return taps;
}

} // namespace

void lumaFromRgb(const Image8& rgb, Image8& luma)
{
    luma.reshape(rgb.width, rgb.height, 1);
    const size_t pixels = size_t(rgb.width) * size_t(rgb.height);
    const uint8_t* in = rgb.data.data();
    uint8_t* out = luma.data.data();
    for (size_t i = 0; i < pixels; ++i, in += 3) {
        out[i] = bt601Luma(in[0], in[1], in[2]);
    }
}

YCbCrToRgb::YCbCrToRgb(int width, int height, int chromaWidth, int chromaHeight)
    : width_(width), height_(height), chromaWidth_(chromaWidth), chromaHeight_(chromaHeight)
{
    if (chromaWidth_ > 0 && chromaHeight_ > 0) {
        columnTaps_ = upsamplingTaps(width_, chromaWidth_);
        rowTaps_ = upsamplingTaps(height_, chromaHeight_);
        cbRow_.resize(size_t(chromaWidth_));
        crRow_.resize(size_t(chromaWidth_));
    }
}

void YCbCrToRgb::convert(const PlanarYCbCr& picture, Image8& rgb, Image8& luma)
{
    const int w = width_;
    const int h = height_;
    rgb.reshape(w, h, 3);
    luma.reshape(w, h, 1);

    // Limited range puts black at 16 and white at 235, chroma at 128 ± 112.
    const float yOffset = picture.fullRange ? 0.0f : 16.0f;
    const float yScale = picture.fullRange ? 1.0f : 255.0f / 219.0f;
    const float cScale = picture.fullRange ? 1.0f : 255.0f / 224.0f;
    const bool mono = columnTaps_.empty();

    for (int y = 0; y < h; ++y) {
        const uint8_t* yRow = picture.y + size_t(y) * size_t(w);
        uint8_t* out = rgb.row(y);
        uint8_t* lumaOut = luma.row(y);
        if (mono) {
            for (int x = 0; x < w; ++x) {
                const uint8_t v = clampToByte((yRow[x] - yOffset) * yScale);
                out[3 * x] = out[3 * x + 1] = out[3 * x + 2] = v;
                lumaOut[x] = v;
            }
            continue;
        }
        // Vertical chroma interpolation once per row, horizontal per pixel.
        const Tap& rt = rowTaps_[size_t(y)];
        const size_t cw = size_t(chromaWidth_);
        const uint8_t* cb0 = picture.cb + size_t(rt.lower) * cw;
        const uint8_t* cb1 = picture.cb + size_t(rt.upper) * cw;
        const uint8_t* cr0 = picture.cr + size_t(rt.lower) * cw;
        const uint8_t* cr1 = picture.cr + size_t(rt.upper) * cw;
        for (size_t i = 0; i < cw; ++i) {
            cbRow_[i] = float(cb0[i]) + rt.upperWeight * (float(cb1[i]) - float(cb0[i]));
            crRow_[i] = float(cr0[i]) + rt.upperWeight * (float(cr1[i]) - float(cr0[i]));
        }
        for (int x = 0; x < w; ++x) {
            const Tap& ct = columnTaps_[size_t(x)];
            const float cbLo = cbRow_[size_t(ct.lower)];
            const float crLo = crRow_[size_t(ct.lower)];
            const float cbv = cbLo + ct.upperWeight * (cbRow_[size_t(ct.upper)] - cbLo);
            const float crv = crLo + ct.upperWeight * (crRow_[size_t(ct.upper)] - crLo);
            const float yv = (float(yRow[x]) - yOffset) * yScale;
            const float cbc = (cbv - 128.0f) * cScale;
            const float crc = (crv - 128.0f) * cScale;
            // BT.601 (Kr = 0.299, Kb = 0.114) inverted.
            out[3 * x] = clampToByte(yv + 1.402f * crc);
            out[3 * x + 1] = clampToByte(yv - 0.344136f * cbc - 0.714136f * crc);
            out[3 * x + 2] = clampToByte(yv + 1.772f * cbc);
            lumaOut[x] = clampToByte(yv);
        }
    }
}

} // namespace lumar
