// The fake camera's environment map in shared-exponent form: a map decoded from a .hdr file
// fits it and reads back bit for bit (intensity applied as before); a map that does not fit
// is kept as floats and reads back the same way.
#include <algorithm>
#include <cstring>
#include <filesystem>

#include <gtest/gtest.h>

#include "capture/shared_exponent_image.h"
#include "gles_renderer/assets/environment_map.h"

namespace lumar {
namespace {

// Every texel of `image` reads back as max(v, 0) · scale, bit for bit.
void expectReadsBack(const SharedExponentImage& stored, const ImageF& image, float scale)
{
    ASSERT_EQ(stored.width(), image.width);
    ASSERT_EQ(stored.height(), image.height);
    for (int y = 0; y < image.height; ++y) {
        for (int x = 0; x < image.width; ++x) {
            const glm::vec3 v = stored.at(x, y);
            for (int c = 0; c < 3; ++c) {
                const float expected = std::max(image.at(x, y)[c], 0.0f) * scale;
                ASSERT_EQ(std::memcmp(&v[c], &expected, sizeof expected), 0)
                    << "texel " << x << "," << y << " channel " << c << ": " << v[c] << " vs " << expected;
            }
        }
    }
}

TEST(SharedExponentImage, AnHdrFilesMapFitsAndReadsBackBitForBit)
{
    const ImageF sunset =
        loadHdrImage(std::filesystem::path(LUMAR_SOURCE_DIR) / "daemon/assets/env/venice_sunset_1k.hdr");
    for (const float intensity : {1.0f, 0.37f, 2.5f}) {
        const SharedExponentImage stored(sunset, intensity);
        EXPECT_TRUE(stored.compact());
        expectReadsBack(stored, sunset, intensity);
    }
}

TEST(SharedExponentImage, AMapThatDoesNotFitIsKeptAsItsFloats)
{
    ImageF image(3, 2, 3);
    for (size_t i = 0; i < image.data.size(); ++i) {
        image.data[i] = float(i) * 0.25f; // 8-bit mantissas: fits
    }
    EXPECT_TRUE(SharedExponentImage(image, 1.0f).compact());
    for (const float odd : {0.1f, -1.0f, -0.0f, 1e-42f}) {
        image.data[4] = odd; // 0.1: more mantissa bits than 8; negatives; below the exponent range
        const SharedExponentImage stored(image, 1.5f);
        EXPECT_FALSE(stored.compact()) << odd;
        expectReadsBack(stored, image, 1.5f);
    }
}

} // namespace
} // namespace lumar
