// BT.601 conversions shared by the capture sources: what the tracker's luma plane is and how
// a YCbCr file becomes sRGB.
#pragma once

#include <cstdint>
#include <vector>

#include "core/image.h"

namespace lumar {

// BT.601 luma of 8-bit sRGB, round(0.299 R + 0.587 G + 0.114 B), in exact integer arithmetic.
inline uint8_t bt601Luma(uint8_t r, uint8_t g, uint8_t b)
{
    return uint8_t((299u * r + 587u * g + 114u * b + 500u) / 1000u);
}

// Fills `luma` (1 channel, reshaped to rgb's size) from a 3-channel image.
void lumaFromRgb(const Image8& rgb, Image8& luma);

// The planes of one 8-bit YCbCr picture, tightly packed; cb/cr are null for monochrome.
struct PlanarYCbCr {
    const uint8_t* y = nullptr;
    const uint8_t* cb = nullptr;
    const uint8_t* cr = nullptr;
    bool fullRange = false; // false: Y in [16, 235], Cb/Cr in [16, 240]
};

// BT.601 YCbCr → sRGB for pictures of one geometry: chroma planes of chromaWidth ×
// chromaHeight samples (0 × 0 for monochrome), upsampled bilinearly with each chroma sample
// centred on the luma samples it covers. The taps are computed once, so converting a stream
// allocates nothing per frame.
//
// Ours rather than libyuv's I420ToRGB24MatrixFilter (bilinear), measured with
// tests/tools/ycbcr_conversion_bench against the exact formula on bilinearly interpolated
// chroma: ours within 0.50 code values, libyuv's within 3.00 (limited range; 2.03 full), green
// biased by -0.04 to -0.07. libyuv is 11-40x faster, but file playback is not the live path.
class YCbCrToRgb {
public:
    YCbCrToRgb(int width, int height, int chromaWidth, int chromaHeight);

    // Writes `rgb` (3 channels) and `luma` (1 channel: the Y samples expanded to full range,
    // so the tracker reads the camera's own luma, not one rebuilt from upsampled chroma).
    // The picture must have the geometry given to the constructor.
    void convert(const PlanarYCbCr& picture, Image8& rgb, Image8& luma);

    // Where output sample i reads a subsampled plane: lower neighbour and upper one's weight.
    struct Tap {
        int lower = 0;
        int upper = 0;
        float upperWeight = 0.0f;
    };

private:
    int width_;
    int height_;
    int chromaWidth_;
    int chromaHeight_;
    std::vector<Tap> columnTaps_;
    std::vector<Tap> rowTaps_;
    std::vector<float> cbRow_; // scratch: one vertically interpolated chroma row
    std::vector<float> crRow_;
};

} // namespace lumar
