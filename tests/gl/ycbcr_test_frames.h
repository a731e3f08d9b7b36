// YCbCr frames for the GL tests of the camera background (ycbcr_background_test.cpp,
// dmabuf_device_test.cpp): the layout × matrix × range cases, frame content as a driver
// writes it (colour bars or random bytes at a given stride), the capture thread's CPU
// converter as the reference, and a byte-wise comparison.
#pragma once

#include <algorithm>
#include <cstdint>
#include <cstdlib>
#include <random>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <linux/videodev2.h>

#include "capture/v4l2/ycbcr_to_rgb.h"
#include "core/image.h"
#include "core/ycbcr_image.h"
#include "vcam/vcam_pattern.h"

namespace lumar::test {

struct YcbcrCase {
    YCbCrLayout layout;
    YCbCrColorimetry colorimetry;
};

inline std::string describe(const YcbcrCase& c)
{
    return std::string(c.layout == YCbCrLayout::Nv12 ? "NV12" : "YUYV") +
           (c.colorimetry.matrix == YCbCrMatrix::Bt709 ? " BT.709" : " BT.601") +
           (c.colorimetry.fullRange ? " full" : " limited");
}

// NV12 and YUYV, each with both matrices and both ranges.
inline std::vector<YcbcrCase> allYcbcrCases()
{
    std::vector<YcbcrCase> cases;
    for (YCbCrLayout layout : {YCbCrLayout::Nv12, YCbCrLayout::Yuyv})
        for (YCbCrMatrix matrix : {YCbCrMatrix::Bt601, YCbCrMatrix::Bt709})
            for (bool fullRange : {false, true})
                cases.push_back({layout, {matrix, fullRange}});
    return cases;
}

// The bytes a width x height frame of `c`'s layout takes at `bytesPerLine` (NV12's chroma
// rows after the luma rows, at the same stride).
inline size_t ycbcrFrameBytes(const YcbcrCase& c, size_t bytesPerLine, int height)
{
    return bytesPerLine * size_t(height) * (c.layout == YCbCrLayout::Nv12 ? 3 : 2) / 2;
}

// Writes a frame into `out` as the driver would: the virtual camera's colour bars (frame
// `seed` of its pattern), or random bytes seeded with `seed` (footroom and headroom
// excursions included).
inline void fillYcbcrFrame(const YcbcrCase& c, bool random, unsigned seed, int width, int height, size_t bytesPerLine,
                           uint8_t* out)
{
    const bool nv12 = c.layout == YCbCrLayout::Nv12;
    if (random) {
        std::mt19937 engine(seed);
        std::uniform_int_distribution<int> byte(0, 255);
        std::generate_n(out, ycbcrFrameBytes(c, bytesPerLine, height), [&] { return uint8_t(byte(engine)); });
        return;
    }
    vcam::PatternFormat format;
    format.pixelFormat = nv12 ? V4L2_PIX_FMT_NV12 : V4L2_PIX_FMT_YUYV;
    format.width = width;
    format.height = height;
    format.bytesPerLine = bytesPerLine;
    format.bt709 = c.colorimetry.matrix == YCbCrMatrix::Bt709;
    format.fullRange = c.colorimetry.fullRange;
    vcam::drawPattern(format, int64_t(seed), out);
}

// The capture thread's conversion of that frame: what the GPU background must match.
inline Image8 cpuYcbcrReference(const YcbcrCase& c, const uint8_t* bytes, size_t bytesPerLine, int width, int height)
{
    const YCbCrConverter converter(c.colorimetry);
    Image8 rgb, luma;
    if (c.layout == YCbCrLayout::Nv12)
        converter.convertNv12(bytes, bytesPerLine, bytes + bytesPerLine * size_t(height), bytesPerLine, width, height,
                              rgb, luma);
    else
        converter.convertYuyv(bytes, bytesPerLine, width, height, rgb, luma);
    return rgb;
}

struct ByteDifference {
    int worst = 0;        // the largest difference of one byte
    size_t differing = 0; // bytes that differ at all
};

inline ByteDifference compareBytes(const Image8& out, const Image8& expected)
{
    EXPECT_EQ(out.data.size(), expected.data.size());
    ByteDifference difference;
    for (size_t i = 0; i < std::min(out.data.size(), expected.data.size()); ++i) {
        const int d = std::abs(int(out.data[i]) - int(expected.data[i]));
        difference.worst = std::max(difference.worst, d);
        difference.differing += d != 0;
    }
    return difference;
}

} // namespace lumar::test
