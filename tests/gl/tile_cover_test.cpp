// TileCover (gles_renderer/scene/tile_cover.h): the tiles a convex window-space polygon
// touches, as disjoint rectangles. Conservative (every pixel inside the polygon lies in a
// marked tile) and tight (a tile farther than the margin from the polygon stays unmarked).
#include <cmath>
#include <numbers>
#include <vector>

#include <gtest/gtest.h>

#include "gles_renderer/scene/tile_cover.h"

namespace lumar {
namespace {

bool inConvex(const std::vector<glm::dvec2>& polygon, const glm::dvec2& p)
{
    if (polygon.size() < 3)
        return false; // a point or a segment: its edges stand for it
    bool positive = false, negative = false;
    for (size_t i = 0; i < polygon.size(); ++i) {
        const glm::dvec2 a = polygon[i], b = polygon[(i + 1) % polygon.size()];
        const double side = (b.x - a.x) * (p.y - a.y) - (b.y - a.y) * (p.x - a.x);
        positive = positive || side > 0.0;
        negative = negative || side < 0.0;
    }
    return !(positive && negative);
}

// The distance from a tile (a rectangle) to a convex polygon is at most `margin` where some
// point of the tile, sampled finely, lies within the polygon grown by `margin`: checked here
// by sampling the tile and the polygon's edges.
double distanceToTile(const std::vector<glm::dvec2>& polygon, int x0, int y0, int x1, int y1)
{
    double best = 1e30;
    for (size_t i = 0; i < polygon.size(); ++i) {
        const glm::dvec2 a = polygon[i], b = polygon[(i + 1) % polygon.size()];
        for (int k = 0; k <= 200; ++k) {
            const glm::dvec2 p = a + (b - a) * (k / 200.0);
            const double dx = std::max({double(x0) - p.x, 0.0, p.x - double(x1)});
            const double dy = std::max({double(y0) - p.y, 0.0, p.y - double(y1)});
            best = std::min(best, std::hypot(dx, dy));
        }
    }
    if (inConvex(polygon, {0.5 * (x0 + x1), 0.5 * (y0 + y1)}))
        best = 0.0;
    return best;
}

TEST(TileCover, MarksEveryTileAConvexPolygonTouchesAndNoFartherOne)
{
    constexpr int width = 203, height = 117, tile = 8;
    constexpr double margin = 1.5;
    // A turned parallelogram, an ellipse's circumscribed 16-gon reaching out of the viewport,
    // a thin sliver and a point.
    std::vector<std::vector<glm::dvec2>> polygons = {
        {{30.2, 20.7}, {90.4, 35.1}, {110.9, 80.3}, {50.6, 65.8}},
        {},
        {{150.0, 10.0}, {151.0, 100.0}, {151.5, 100.0}},
        {{20.0, 100.0}},
    };
    for (int k = 0; k < 16; ++k) {
        const double a = 2.0 * std::numbers::pi * k / 16;
        polygons[1].emplace_back(190.0 + 40.0 * std::cos(a) - 10.0 * std::sin(a), 60.0 + 25.0 * std::sin(a));
    }
    for (const auto& polygon : polygons) {
        TileCover cover(width, height, tile);
        cover.addConvex(polygon, margin);
        // The rectangles: disjoint, within the viewport, exactly the marked tiles.
        std::vector<int> count(size_t(width * height), 0);
        for (const PixelRect& r : cover.rects()) {
            ASSERT_FALSE(r.empty());
            ASSERT_GE(r.x0, 0);
            ASSERT_GE(r.y0, 0);
            ASSERT_LE(r.x1, width);
            ASSERT_LE(r.y1, height);
            for (int y = r.y0; y < r.y1; ++y)
                for (int x = r.x0; x < r.x1; ++x)
                    ++count[size_t(y * width + x)];
        }
        for (int row = 0; row < cover.rows(); ++row)
            for (int column = 0; column < cover.columns(); ++column) {
                const int x0 = column * tile, y0 = row * tile;
                const int x1 = std::min(x0 + tile, width), y1 = std::min(y0 + tile, height);
                const double distance = distanceToTile(polygon, x0, y0, x1, y1);
                if (distance <= margin * 0.99) {
                    EXPECT_TRUE(cover.marked(column, row)) << column << "," << row << " at " << distance;
                }
                if (distance > margin * std::numbers::sqrt2 + 0.01) {
                    EXPECT_FALSE(cover.marked(column, row)) << column << "," << row << " at " << distance;
                }
                for (int y = y0; y < y1; ++y)
                    for (int x = x0; x < x1; ++x)
                        ASSERT_EQ(count[size_t(y * width + x)], cover.marked(column, row) ? 1 : 0) << x << "," << y;
            }
    }
}

TEST(TileCover, ANonFiniteVertexMarksEverything)
{
    TileCover cover(64, 40, 16);
    const std::vector<glm::dvec2> polygon = {{1.0, 1.0}, {std::nan(""), 3.0}, {5.0, 5.0}};
    cover.addConvex(polygon, 0.0);
    const std::vector<PixelRect> rects = cover.rects();
    ASSERT_EQ(rects.size(), 1u);
    EXPECT_EQ(rects[0].x1 - rects[0].x0, 64);
    EXPECT_EQ(rects[0].y1 - rects[0].y0, 40);
}

TEST(TileCover, APolygonOutsideTheViewportMarksNothing)
{
    TileCover cover(64, 40, 16);
    const std::vector<glm::dvec2> polygon = {{-30.0, 10.0}, {-5.0, 12.0}, {-10.0, 30.0}};
    cover.addConvex(polygon, 1.0);
    EXPECT_TRUE(cover.rects().empty());
}

// Labels (ShadowPass shades each tile with only what reaches it): each tile carries the union
// of the labels of the polygons that marked it; labelledRects covers exactly the marked
// tiles, disjointly, each rectangle's tiles all of its label, grouped by label; mergeLabels
// gives every marked tile of a block the union of the block's labels and marks no new tile.
TEST(TileCover, LabelledRectanglesCarryTheUnionOfTheirTilesLabels)
{
    constexpr int width = 150, height = 90, tile = 10;
    TileCover cover(width, height, tile);
    const std::vector<glm::dvec2> a = {{5.0, 5.0}, {70.0, 5.0}, {70.0, 50.0}, {5.0, 50.0}};
    const std::vector<glm::dvec2> b = {{40.0, 30.0}, {120.0, 30.0}, {120.0, 80.0}, {40.0, 80.0}};
    const std::vector<glm::dvec2> c = {{130.0, 2.0}, {140.0, 2.0}, {135.0, 12.0}};
    cover.addConvex(a, 0.0, 1u);
    cover.addConvex(b, 0.0, 2u);
    cover.addConvex(c, 0.0, 1u << 16);
    EXPECT_EQ(cover.label(0, 0), 1u);
    EXPECT_EQ(cover.label(5, 4), 3u); // (55, 45): both rectangles
    EXPECT_EQ(cover.label(10, 7), 2u);
    EXPECT_EQ(cover.label(13, 0), 1u << 16);
    EXPECT_EQ(cover.label(14, 8), 0u);
    const auto check = [&](const TileCover& labelled) {
        std::vector<int> count(size_t(width * height), 0);
        uint32_t previous = 0;
        for (const auto& [r, label] : labelled.labelledRects()) {
            ASSERT_FALSE(r.empty());
            EXPECT_GE(label, previous) << "grouped by label";
            previous = label;
            for (int y = r.y0; y < r.y1; ++y)
                for (int x = r.x0; x < r.x1; ++x) {
                    ++count[size_t(y * width + x)];
                    ASSERT_EQ(labelled.label(x / tile, y / tile), label) << x << "," << y;
                }
        }
        for (int y = 0; y < height; ++y)
            for (int x = 0; x < width; ++x)
                ASSERT_EQ(count[size_t(y * width + x)], labelled.marked(x / tile, y / tile) ? 1 : 0) << x << "," << y;
    };
    check(cover);
    TileCover merged = cover;
    merged.mergeLabels(4);
    check(merged);
    for (int row = 0; row < cover.rows(); ++row)
        for (int column = 0; column < cover.columns(); ++column) {
            uint32_t block = 0;
            for (int r = row / 4 * 4; r < std::min(row / 4 * 4 + 4, cover.rows()); ++r)
                for (int k = column / 4 * 4; k < std::min(column / 4 * 4 + 4, cover.columns()); ++k)
                    block |= cover.label(k, r);
            EXPECT_EQ(merged.label(column, row), cover.marked(column, row) ? block : 0u) << column << "," << row;
        }
    EXPECT_EQ(merged.rects().size(), cover.rects().size()) << "the same tiles";
}

} // namespace
// subtract unmarks exactly the tiles the other cover marks (ShadowPass's depth pass leaves out
// the darkening's tiles where the apply pass writes the depth), and a cover of another grid
// leaves it as it was.
TEST(TileCover, SubtractUnmarksTheOtherCoversTiles)
{
    constexpr int width = 150, height = 90, tile = 10;
    TileCover cover(width, height, tile);
    cover.addConvex(std::vector<glm::dvec2>{{5.0, 5.0}, {120.0, 5.0}, {120.0, 80.0}, {5.0, 80.0}}, 0.0, 3u);
    TileCover other(width, height, tile);
    other.addConvex(std::vector<glm::dvec2>{{35.0, 25.0}, {64.0, 25.0}, {64.0, 44.0}, {35.0, 44.0}}, 0.0);
    TileCover result = cover;
    result.subtract(other);
    int unmarked = 0;
    for (int row = 0; row < cover.rows(); ++row)
        for (int column = 0; column < cover.columns(); ++column) {
            EXPECT_EQ(result.label(column, row), other.marked(column, row) ? 0u : cover.label(column, row))
                << column << "," << row;
            unmarked += cover.marked(column, row) && !result.marked(column, row);
        }
    EXPECT_EQ(unmarked, 4 * 3); // columns 3-6 of rows 2-4
    TileCover coarse(width, height, 2 * tile);
    coarse.addAll();
    TileCover unchanged = cover;
    unchanged.subtract(coarse);
    for (int row = 0; row < cover.rows(); ++row)
        for (int column = 0; column < cover.columns(); ++column)
            EXPECT_EQ(unchanged.label(column, row), cover.label(column, row));
}

} // namespace lumar
