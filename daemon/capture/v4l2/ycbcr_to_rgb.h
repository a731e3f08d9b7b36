// Camera YCbCr layouts (YUYV 4:2:2, NV12 4:2:0, GREY) → 3-channel sRGB plus the tracker's
// luma plane, for either matrix (BT.601 / BT.709) and either quantization range, as the V4L2
// driver reports them. Chroma is replicated over the luma samples it covers (no
// interpolation): the tracker reads luma only, and replication keeps a 720p frame cheap.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>

#include "core/image.h"
#include "core/ycbcr_image.h"

namespace lumar {

// One colorimetry's conversion as lookup tables in 16.16 fixed point, built once per stream.
//
// Ours rather than libyuv's (Debian 0.0~git20230123), measured with
// tests/tools/ycbcr_conversion_bench against the exact formula over every (Y, Cb, Cr) triple:
// ours is within 0.50 code values everywhere with no bias (|mean signed error| <= 0.001);
// libyuv's NV12/YUYV → RGB, with 6-bit coefficients and the blue one capped at 2.0, is off by
// up to 2.42 (BT.601 limited), 13.1 (BT.709 limited), 1.27 (601 full) and 0.91 (709 full),
// biased by -0.01 to -0.04. It is 2-3x (limited, luma expansion included) to 10-40x (full) faster
// at 720p, but the CPU path is the reference the GPU conversion is held to (within one code
// value, < 0.1 % of bytes differing) and is asserted within 0.52 of the exact values. The
// exact identities (full-range luma, GREY) are plain copies here.
class YCbCrConverter {
public:
    explicit YCbCrConverter(YCbCrColorimetry colorimetry);

    // Each reads `height` rows of `width` pixels; strides are in bytes. `width` must be even
    // for YUYV and NV12, `height` even for NV12 (V4L2 guarantees both for these formats).
    void convertYuyv(const uint8_t* data, size_t stride, int width, int height, Image8& rgb, Image8& luma) const;
    void convertNv12(const uint8_t* yPlane, size_t yStride, const uint8_t* uvPlane, size_t uvStride, int width,
                     int height, Image8& rgb, Image8& luma) const;
    void convertGrey(const uint8_t* data, size_t stride, int width, int height, Image8& rgb, Image8& luma) const;

    // Only the tracker's luma (the same values the conversions write), from Y samples
    // `step` bytes apart: 1 for an NV12 Y plane, 2 for YUYV.
    void convertLuma(const uint8_t* data, size_t stride, size_t step, int width, int height, Image8& luma) const;

    [[nodiscard]] YCbCrColorimetry colorimetry() const { return colorimetry_; }

private:
    // One pixel from its Y and the (already looked-up) chroma terms.
    void writePixel(uint8_t yValue, int32_t redChroma, int32_t greenChroma, int32_t blueChroma, uint8_t* rgbOut,
                    uint8_t* lumaOut) const;

    YCbCrColorimetry colorimetry_;
    std::array<int32_t, 256> yTerm_{}; // Y expanded to full range, 16.16
    std::array<uint8_t, 256> luma_{};  // the same rounded and clamped: the tracker's luma
    std::array<int32_t, 256> crToRed_{};
    std::array<int32_t, 256> cbToGreen_{}; // both green terms are subtracted
    std::array<int32_t, 256> crToGreen_{};
    std::array<int32_t, 256> cbToBlue_{};
};

} // namespace lumar
