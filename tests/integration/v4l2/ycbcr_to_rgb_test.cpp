// The CPU YCbCr → RGB conversion of the V4L2 backend against the virtual camera's colour
// bars, whose YCbCr values come from the forward BT.601/709 equations (tests/vcam), and
// against hand-computed reference values.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <vector>

#include <gtest/gtest.h>
#include <linux/videodev2.h>

#include "capture/v4l2/ycbcr_to_rgb.h"
#include "vcam/vcam_pattern.h"

namespace lumar {
namespace {

struct Case {
    uint32_t pixelFormat;
    bool bt709;
    bool fullRange;
};

size_t bytesPerLine(uint32_t pixelFormat, int width)
{
    return size_t(width) * (pixelFormat == V4L2_PIX_FMT_YUYV ? 2 : 1);
}

size_t imageSize(uint32_t pixelFormat, int width, int height)
{
    const size_t plane = bytesPerLine(pixelFormat, width) * size_t(height);
    return pixelFormat == V4L2_PIX_FMT_NV12 ? plane + plane / 2 : plane;
}

void convert(const YCbCrConverter& converter, uint32_t pixelFormat, const std::vector<uint8_t>& data, int width,
             int height, Image8& rgb, Image8& luma)
{
    const size_t stride = bytesPerLine(pixelFormat, width);
    if (pixelFormat == V4L2_PIX_FMT_YUYV) {
        converter.convertYuyv(data.data(), stride, width, height, rgb, luma);
    } else if (pixelFormat == V4L2_PIX_FMT_NV12) {
        converter.convertNv12(data.data(), stride, data.data() + stride * size_t(height), stride, width, height, rgb,
                              luma);
    } else {
        converter.convertGrey(data.data(), stride, width, height, rgb, luma);
    }
}

// Largest |decoded − expected| over the centre column of every bar, all channels.
int worstBarError(const Image8& rgb, bool grey)
{
    int worst = 0;
    const auto& bars = vcam::colourBars();
    for (size_t bar = 0; bar < bars.size(); ++bar) {
        const int x = int((2 * bar + 1) * size_t(rgb.width) / 16);
        const uint8_t* pixel = rgb.at(x, rgb.height / 4);
        int expected[3] = {bars[bar].r, bars[bar].g, bars[bar].b};
        if (grey) {
            // GREY carries only the luma: R = G = B = Y, which the BT.601 luma of the bar is.
            const int y = int((299 * bars[bar].r + 587 * bars[bar].g + 114 * bars[bar].b + 500) / 1000);
            expected[0] = expected[1] = expected[2] = y;
        }
        for (int c = 0; c < 3; ++c) {
            worst = std::max(worst, std::abs(int(pixel[c]) - expected[c]));
        }
    }
    return worst;
}

class ColourBarsTest : public ::testing::TestWithParam<Case> {};

TEST_P(ColourBarsTest, DecodeWithinTwoCodeValues)
{
    const Case c = GetParam();
    const int width = 640;
    const int height = 480;
    std::vector<uint8_t> data(imageSize(c.pixelFormat, width, height));
    vcam::drawPattern({c.pixelFormat, width, height, bytesPerLine(c.pixelFormat, width), c.bt709, c.fullRange}, 0,
                      data.data());
    const YCbCrConverter converter({c.bt709 ? YCbCrMatrix::Bt709 : YCbCrMatrix::Bt601, c.fullRange});
    Image8 rgb;
    Image8 luma;
    convert(converter, c.pixelFormat, data, width, height, rgb, luma);
    ASSERT_EQ(rgb.width, width);
    ASSERT_EQ(luma.height, height);
    EXPECT_LE(worstBarError(rgb, c.pixelFormat == V4L2_PIX_FMT_GREY), 2);
}

INSTANTIATE_TEST_SUITE_P(AllFormatsMatricesRanges, ColourBarsTest,
                         ::testing::Values(Case{V4L2_PIX_FMT_YUYV, false, false}, Case{V4L2_PIX_FMT_YUYV, false, true},
                                           Case{V4L2_PIX_FMT_YUYV, true, false}, Case{V4L2_PIX_FMT_YUYV, true, true},
                                           Case{V4L2_PIX_FMT_NV12, false, false}, Case{V4L2_PIX_FMT_NV12, false, true},
                                           Case{V4L2_PIX_FMT_NV12, true, false}, Case{V4L2_PIX_FMT_NV12, true, true},
                                           // GREY: BT.601 luma only (the reference below is 601's).
                                           Case{V4L2_PIX_FMT_GREY, false, false},
                                           Case{V4L2_PIX_FMT_GREY, false, true}));

TEST(YCbCrConverter, WrongMatrixIsDetected)
{
    // The check above can fail: BT.709 bars decoded as BT.601 miss by far more than 2.
    const int width = 640;
    const int height = 480;
    std::vector<uint8_t> data(imageSize(V4L2_PIX_FMT_YUYV, width, height));
    vcam::drawPattern({V4L2_PIX_FMT_YUYV, width, height, bytesPerLine(V4L2_PIX_FMT_YUYV, width), true, false}, 0,
                      data.data());
    Image8 rgb;
    Image8 luma;
    convert(YCbCrConverter({YCbCrMatrix::Bt601, false}), V4L2_PIX_FMT_YUYV, data, width, height, rgb, luma);
    EXPECT_GT(worstBarError(rgb, false), 10);
}

TEST(YCbCrConverter, HandComputedLimitedRangeValues)
{
    // Limited BT.601: Y=16 is black, Y=235 white, (Y, Cb, Cr) = (81, 90, 240) is red:
    // R = 255/219·65 + 1.402·255/224·112 = 75.68 + 178.75 → 254.4; G, B near 0.
    const uint8_t yuyv[8] = {16, 128, 235, 128, 81, 90, 81, 240};
    Image8 rgb;
    Image8 luma;
    YCbCrConverter({YCbCrMatrix::Bt601, false}).convertYuyv(yuyv, 8, 4, 1, rgb, luma);
    const uint8_t expected[12] = {0, 0, 0, 255, 255, 255, 254, 0, 0, 254, 0, 0};
    for (int i = 0; i < 12; ++i) {
        EXPECT_NEAR(rgb.data[size_t(i)], expected[i], 1) << "sample " << i;
    }
    EXPECT_EQ(luma.data[0], 0);
    EXPECT_EQ(luma.data[1], 255);
    EXPECT_EQ(luma.data[2], 76); // (81 − 16)·255/219 = 75.7
}

TEST(YCbCrConverter, WithinRoundingOfTheExactFormulaEverywhere)
{
    // The contract that kept libyuv out (its 6-bit coefficients miss by up to 13 code values,
    // see ycbcr_to_rgb.h): every Y, chroma on a grid, footroom and headroom included.
    for (const YCbCrColorimetry colorimetry :
         {YCbCrColorimetry{YCbCrMatrix::Bt601, false}, YCbCrColorimetry{YCbCrMatrix::Bt601, true},
          YCbCrColorimetry{YCbCrMatrix::Bt709, false}, YCbCrColorimetry{YCbCrMatrix::Bt709, true}}) {
        const bool bt709 = colorimetry.matrix == YCbCrMatrix::Bt709;
        const double kr = bt709 ? 0.2126 : 0.299;
        const double kb = bt709 ? 0.0722 : 0.114;
        const double kg = 1.0 - kr - kb;
        const double yScale = colorimetry.fullRange ? 1.0 : 255.0 / 219.0;
        const double cScale = colorimetry.fullRange ? 1.0 : 255.0 / 224.0;
        const double yOffset = colorimetry.fullRange ? 0.0 : 16.0;
        const YCbCrConverter converter(colorimetry);
        std::vector<uint8_t> yuyv;
        for (int cr = 0; cr < 256; cr += 5)
            for (int cb = 0; cb < 256; cb += 5)
                for (int y = 0; y < 256; y += 2)
                    yuyv.insert(yuyv.end(), {uint8_t(y), uint8_t(cb), uint8_t(y + 1), uint8_t(cr)});
        const int width = int(yuyv.size() / 2);
        Image8 rgb;
        Image8 luma;
        converter.convertYuyv(yuyv.data(), yuyv.size(), width, 1, rgb, luma);
        double worst = 0.0;
        for (int x = 0; x < width; ++x) {
            const uint8_t* group = yuyv.data() + size_t(x / 2) * 4;
            const double yv = (group[(x % 2) * 2] - yOffset) * yScale;
            const double u = (group[1] - 128.0) * cScale;
            const double v = (group[3] - 128.0) * cScale;
            const double exact[3] = {yv + 2.0 * (1.0 - kr) * v,
                                     yv - 2.0 * (1.0 - kb) * kb / kg * u - 2.0 * (1.0 - kr) * kr / kg * v,
                                     yv + 2.0 * (1.0 - kb) * u};
            for (int c = 0; c < 3; ++c)
                worst = std::max(worst, std::abs(rgb.at(x, 0)[c] - std::clamp(exact[c], 0.0, 255.0)));
            EXPECT_EQ(luma.data[size_t(x)], uint8_t(std::clamp(std::lround(yv), 0L, 255L))) << x;
        }
        EXPECT_LE(worst, 0.5 + 1e-3) << (bt709 ? "BT.709" : "BT.601") << (colorimetry.fullRange ? " full" : " limited");
    }
}

TEST(YCbCrConverter, LumaOnlyAndGreyMatchTheConversionsLuma)
{
    // convertLuma and convertGrey copy the Y bytes in full range and look them up in limited
    // range: the same bytes convertNv12/convertYuyv write, for every Y value.
    for (const bool fullRange : {false, true}) {
        const YCbCrConverter converter({YCbCrMatrix::Bt601, fullRange});
        std::vector<uint8_t> yuyv(1024);
        std::vector<uint8_t> grey(512);
        for (int i = 0; i < 512; ++i) {
            yuyv[size_t(2 * i)] = grey[size_t(i)] = uint8_t(i % 256);
            yuyv[size_t(2 * i + 1)] = uint8_t(128);
        }
        Image8 rgb, luma, lumaOnly, greyRgb, greyLuma;
        converter.convertYuyv(yuyv.data(), 512, 256, 2, rgb, luma);
        converter.convertLuma(yuyv.data(), 512, 2, 256, 2, lumaOnly);
        EXPECT_EQ(lumaOnly.data, luma.data);
        converter.convertLuma(grey.data(), 256, 1, 256, 2, lumaOnly);
        EXPECT_EQ(lumaOnly.data, luma.data);
        converter.convertGrey(grey.data(), 256, 256, 2, greyRgb, greyLuma);
        EXPECT_EQ(greyLuma.data, luma.data);
        EXPECT_EQ(greyRgb.data, rgb.data); // Cb = Cr = 128: R = G = B = luma
        if (fullRange) {
            EXPECT_EQ(greyLuma.data, grey);
        }
    }
}

TEST(YCbCrConverter, ConversionCostAt720p)
{
    // Measured, not asserted (DESIGN.md §9): the figure goes to the test log.
    const int width = 1280;
    const int height = 720;
    for (uint32_t format : {V4L2_PIX_FMT_YUYV, V4L2_PIX_FMT_NV12, V4L2_PIX_FMT_GREY}) {
        std::vector<uint8_t> data(imageSize(format, width, height));
        vcam::drawPattern({format, width, height, bytesPerLine(format, width), false, false}, 0, data.data());
        const YCbCrConverter converter({YCbCrMatrix::Bt601, false});
        Image8 rgb;
        Image8 luma;
        convert(converter, format, data, width, height, rgb, luma); // warm-up, allocates
        const int repetitions = 20;
        const auto start = std::chrono::steady_clock::now();
        for (int i = 0; i < repetitions; ++i) {
            convert(converter, format, data, width, height, rgb, luma);
        }
        const double ms =
            std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count() / repetitions;
        const char name[5] = {char(format & 0xff), char((format >> 8) & 0xff), char((format >> 16) & 0xff),
                              char(format >> 24), 0};
        std::printf("[ cost     ] %s 1280x720 -> RGB + luma: %.3f ms/frame\n", name, ms);
        EXPECT_GT(ms, 0.0);
    }
}

} // namespace
} // namespace lumar
