// Window-space rectangles of pixels, and a disjoint cover of their union: a pass that must
// touch each pixel at most once (a multiplicative blend) can then be drawn once per rectangle
// with the scissor test, over the union alone instead of its bounding rectangle.
#pragma once

#include <algorithm>
#include <span>
#include <vector>

namespace lumar {

// [x0, x1) x [y0, y1).
struct PixelRect {
    int x0 = 0, y0 = 0, x1 = 0, y1 = 0;
    [[nodiscard]] bool empty() const { return x1 <= x0 || y1 <= y0; }
    [[nodiscard]] double area() const { return empty() ? 0.0 : double(x1 - x0) * double(y1 - y0); }
    [[nodiscard]] bool overlaps(const PixelRect& r) const
    {
        return !empty() && !r.empty() && r.x0 < x1 && x0 < r.x1 && r.y0 < y1 && y0 < r.y1;
    }
};

// The bounding rectangle of a and b; an empty one adds nothing.
[[nodiscard]] inline PixelRect bounding(const PixelRect& a, const PixelRect& b)
{
    if (a.empty())
        return b;
    if (b.empty())
        return a;
    return {std::min(a.x0, b.x0), std::min(a.y0, b.y0), std::max(a.x1, b.x1), std::max(a.y1, b.y1)};
}

// The rectangle both a and b cover; empty (not necessarily {}) where they do not overlap.
[[nodiscard]] inline PixelRect intersection(const PixelRect& a, const PixelRect& b)
{
    return {std::max(a.x0, b.x0), std::max(a.y0, b.y0), std::min(a.x1, b.x1), std::min(a.y1, b.y1)};
}

// Disjoint rectangles whose union is the union of `rects` (empty ones ignored): the grid of
// every rectangle's edges, its covered cells merged into runs along rows, and runs of equal
// span in consecutive rows merged into one rectangle.
std::vector<PixelRect> disjointCover(std::span<const PixelRect> rects);

// Rectangles built a row of runs at a time (disjointCover, TileCover): a run with the same
// span as one in the row just above continues that rectangle downwards, so a tall region of
// equal width becomes one rectangle instead of one per row.
class RowRunMerger {
public:
    // `runs`: one row's disjoint runs, all spanning the same rows, below the rows added before.
    void addRow(std::vector<PixelRect> runs);
    // The rectangles: disjoint, their union the union of every run added.
    [[nodiscard]] std::vector<PixelRect> finish() &&;

private:
    std::vector<PixelRect> cover_;
    std::vector<PixelRect> previousRow_; // the runs of the row above, still open
};

} // namespace lumar
