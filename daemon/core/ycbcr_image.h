// A camera frame kept in its YCbCr layout (NV12 or YUYV) with the colorimetry the driver
// reported, so the renderer can upload the planes and convert on the GPU instead of the
// capture thread converting every pixel on the CPU.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

namespace lumar {

enum class YCbCrMatrix { Bt601, Bt709 };

struct YCbCrColorimetry {
    YCbCrMatrix matrix = YCbCrMatrix::Bt601;
    bool fullRange = false; // false: Y in [16, 235], Cb/Cr in [16, 240]
};

enum class YCbCrLayout {
    None, // no raw frame: the RGB image is the frame
    Nv12, // plane 0: Y, width x height; plane 1: Cb Cr pairs, width/2 pairs x height/2 rows
    Yuyv, // plane 0: Y0 Cb Y1 Cr per two pixels, width/2 groups x height rows; plane 1 unused
};

struct YCbCrImage {
    YCbCrLayout layout = YCbCrLayout::None;
    int width = 0; // pixels (even)
    int height = 0;
    YCbCrColorimetry colorimetry;
    // Owned copies, reused from frame to frame; strides in bytes.
    std::vector<uint8_t> plane0;
    std::vector<uint8_t> plane1;
    size_t stride0 = 0;
    size_t stride1 = 0;

    [[nodiscard]] bool empty() const { return layout == YCbCrLayout::None; }
};

} // namespace lumar
