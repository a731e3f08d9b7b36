// The tag36h11 pattern the fake camera draws must be the official tag images, bit for bit.
#include <cstdio>
#include <string>

#include <gtest/gtest.h>

#include "capture/tag36h11_pattern.h"
#include "core/error.h"
#include "output/frame_writer.h"

namespace lumar {
namespace {

std::filesystem::path shippedTagImage(int id)
{
    char name[64];
    std::snprintf(name, sizeof name, "tag36_11_%05d.png", id);
    return std::filesystem::path(LUMAR_TEST_DATA_DIR) / "apriltag" / "tag36h11" / name;
}

TEST(Tag36h11Pattern, FamilyHas587Codes)
{
    EXPECT_EQ(tag36h11CodeCount(), 587);
}

TEST(Tag36h11Pattern, EqualsTheShippedTagImages)
{
    for (int id = 0; id < 16; ++id) {
        SCOPED_TRACE("id " + std::to_string(id));
        const Image8 png = readImage(shippedTagImage(id), 1);
        ASSERT_EQ(png.width, kTag36h11TotalCells);
        ASSERT_EQ(png.height, kTag36h11TotalCells);
        const TagPattern pattern = tag36h11Pattern(id);
        for (int row = 0; row < kTag36h11TotalCells; ++row) {
            for (int col = 0; col < kTag36h11TotalCells; ++col) {
                const bool pngWhite = *png.at(col, row) > 127;
                const bool patternWhite = pattern[size_t(row * kTag36h11TotalCells + col)] == 255;
                EXPECT_EQ(patternWhite, pngWhite) << "cell row " << row << " col " << col;
            }
        }
    }
}

TEST(Tag36h11Pattern, DistinctIdsGiveDistinctPatterns)
{
    EXPECT_NE(tag36h11Pattern(0), tag36h11Pattern(1));
    EXPECT_NE(tag36h11Pattern(585), tag36h11Pattern(586));
}

TEST(Tag36h11Pattern, RejectsIdsWithoutACode)
{
    EXPECT_THROW(tag36h11Pattern(-1), InputError);
    EXPECT_THROW(tag36h11Pattern(587), InputError);
    EXPECT_NO_THROW(tag36h11Pattern(586));
}

} // namespace
} // namespace lumar
