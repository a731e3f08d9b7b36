#include <cstring>
#include <vector>

#include <gtest/gtest.h>

#include "core/error.h"
#include "gles_renderer/assets/rgba8_conversion.h"

namespace lumar {
namespace {

TEST(Rgba8Conversion, ExpandsOneToFourComponents)
{
    const std::vector<uint8_t> grey = {7, 200};
    const Image8 g = convertToRgba8(grey, 2, 1, 1, 8);
    EXPECT_EQ(g.data, (std::vector<uint8_t>{7, 7, 7, 255, 200, 200, 200, 255}));

    const std::vector<uint8_t> greyAlpha = {9, 100};
    EXPECT_EQ(convertToRgba8(greyAlpha, 1, 1, 2, 8).data, (std::vector<uint8_t>{9, 9, 9, 100}));

    const std::vector<uint8_t> rgb = {1, 2, 3};
    EXPECT_EQ(convertToRgba8(rgb, 1, 1, 3, 8).data, (std::vector<uint8_t>{1, 2, 3, 255}));

    const std::vector<uint8_t> rgba = {1, 2, 3, 4};
    const Image8 out = convertToRgba8(rgba, 1, 1, 4, 8);
    EXPECT_EQ(out.data, rgba);
    EXPECT_EQ(out.channels, 4);
}

TEST(Rgba8Conversion, SixteenBitSamplesRoundToNearest)
{
    // round(v * 255 / 65535): 0 -> 0, 65535 -> 255, 257 * 100 -> 100, 32767 -> 127 (127.498),
    // 32896 -> 128 (128.0).
    const std::vector<uint16_t> samples = {0, 65535, 25700, 32767, 32896, 0};
    std::vector<uint8_t> bytes(samples.size() * 2);
    std::memcpy(bytes.data(), samples.data(), bytes.size());
    const Image8 out = convertToRgba8(bytes, 2, 1, 3, 16);
    EXPECT_EQ(out.data, (std::vector<uint8_t>{0, 255, 100, 255, 127, 128, 0, 255}));
}

TEST(Rgba8Conversion, RejectsInconsistentShapes)
{
    const std::vector<uint8_t> three = {1, 2, 3};
    EXPECT_THROW((void)convertToRgba8(three, 2, 1, 3, 8), InputError); // needs 6 bytes
    EXPECT_THROW((void)convertToRgba8(three, 1, 1, 5, 8), InputError);
    EXPECT_THROW((void)convertToRgba8(three, 1, 1, 3, 32), InputError);
    EXPECT_THROW((void)convertToRgba8(three, 0, 1, 3, 8), InputError);
    EXPECT_THROW((void)convertToRgba8(three, -1, -3, 1, 8), InputError);
}

} // namespace
} // namespace lumar
