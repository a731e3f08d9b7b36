#include <cstdint>
#include <vector>

#include <gtest/gtest.h>

#include "core/pixel_pack.h"

namespace lumar {
namespace {

// Pixel i of a test image: three distinct bytes that differ from pixel to pixel.
std::vector<uint8_t> rgbRamp(size_t pixels)
{
    std::vector<uint8_t> rgb(pixels * 3);
    for (size_t i = 0; i < rgb.size(); ++i)
        rgb[i] = uint8_t(i * 7 + 3);
    return rgb;
}

TEST(PixelPack, ExpandsEveryPixelWithOpaqueAlphaAndWritesNothingPastTheEnd)
{
    for (size_t pixels : {size_t(1), size_t(2), size_t(1280 * 3 + 1)}) {
        const std::vector<uint8_t> rgb = rgbRamp(pixels);
        std::vector<uint8_t> rgba(pixels * 4 + 4, 0xAB); // 4 guard bytes
        expandRgbToRgba(rgb.data(), rgba.data(), pixels);
        for (size_t i = 0; i < pixels; ++i) {
            for (size_t c = 0; c < 3; ++c)
                ASSERT_EQ(rgba[4 * i + c], rgb[3 * i + c]) << "pixel " << i << " channel " << c;
            ASSERT_EQ(rgba[4 * i + 3], 255) << "pixel " << i;
        }
        for (size_t g = pixels * 4; g < rgba.size(); ++g)
            EXPECT_EQ(rgba[g], 0xAB) << "guard byte " << g - pixels * 4;
    }
}

TEST(PixelPack, PacksBackToTheSameRgbAndWritesNothingPastTheEnd)
{
    for (size_t pixels : {size_t(1), size_t(2), size_t(1280 * 3 + 1)}) {
        const std::vector<uint8_t> rgb = rgbRamp(pixels);
        std::vector<uint8_t> rgba(pixels * 4);
        expandRgbToRgba(rgb.data(), rgba.data(), pixels);
        for (size_t i = 0; i < pixels; ++i)
            rgba[4 * i + 3] = uint8_t(i); // alpha must be dropped whatever it is
        std::vector<uint8_t> back(pixels * 3 + 3, 0xCD);
        packRgbaToRgb(rgba.data(), back.data(), pixels);
        for (size_t i = 0; i < rgb.size(); ++i)
            ASSERT_EQ(back[i], rgb[i]) << "byte " << i;
        for (size_t g = rgb.size(); g < back.size(); ++g)
            EXPECT_EQ(back[g], 0xCD) << "guard byte " << g - rgb.size();
    }
}

TEST(PixelPack, ZeroPixelsTouchNothing)
{
    uint8_t in[4] = {1, 2, 3, 4};
    uint8_t out[4] = {9, 9, 9, 9};
    expandRgbToRgba(in, out, 0);
    packRgbaToRgb(in, out, 0);
    EXPECT_EQ(out[0], 9);
    EXPECT_EQ(out[3], 9);
}

} // namespace
} // namespace lumar
