// Which tiles of a viewport a set of convex window-space polygons can touch, as disjoint
// rectangles for the scissor test. ShadowPass shades the real surfaces' darkening only where a
// shadow or a contact can fall: the bounding rectangles of those places on a table covered
// ~87 % of car.toml's frame, the tiles that the places themselves (a shadow's parallelogram, a
// contact's ellipse) touch a small part of it.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include <glm/vec2.hpp>

#include "gles_renderer/scene/pixel_rects.h"

namespace lumar {

class TileCover {
public:
    // A viewport of width x height pixels in square tiles of `tile` pixels (the last row and
    // column cut by the viewport). All three at least 1.
    TileCover(int width, int height, int tile);

    // Marks every tile that the convex polygon (window coordinates in pixels, either winding,
    // any number of vertices: a point and a segment mark the tiles they touch) or the band of
    // `margin` pixels around it overlaps, adding the bits of `label` (not 0) to the tile's
    // label. A vertex that is not finite marks the whole viewport.
    void addConvex(std::span<const glm::dvec2> polygon, double margin, uint32_t label = 1);
    void addAll(uint32_t label = 1);

    // Disjoint rectangles, within the viewport, whose union is the marked tiles: the runs of
    // marked tiles along each row, a run with the same span as the one above it continuing that
    // rectangle downwards.
    [[nodiscard]] std::vector<PixelRect> rects() const;
    // The same tiles as disjoint rectangles of one label each (the union of the labels of the
    // polygons that marked its tiles), grouped by label in increasing order: a pass can shade
    // each rectangle with only what its label says reaches it.
    struct LabelledRect {
        PixelRect rect;
        uint32_t label = 0;
    };
    [[nodiscard]] std::vector<LabelledRect> labelledRects() const;
    // Gives each marked tile the union of the labels of the marked tiles in its block of
    // `blocks` x `blocks` tiles (aligned to the grid): fewer, larger rectangles of one label,
    // each label a superset of what its tiles need.
    void mergeLabels(int blocks);
    // Unmarks the tiles that `other` (a cover of the same viewport and tile size) marks.
    void subtract(const TileCover& other);

    [[nodiscard]] int columns() const { return columns_; }
    [[nodiscard]] int rows() const { return rows_; }
    [[nodiscard]] bool marked(int column, int row) const { return label(column, row) != 0; }
    [[nodiscard]] uint32_t label(int column, int row) const { return cells_[size_t(row * columns_ + column)]; }

private:
    void markRow(int row, double x0, double x1, uint32_t label);
    // Rectangles covering the tiles that `selected` accepts (by label).
    template <typename Selected> [[nodiscard]] std::vector<PixelRect> rectsOf(const Selected& selected) const;

    int width_, height_, tile_;
    int columns_, rows_;
    std::vector<uint32_t> cells_; // each tile's label, 0 unmarked
};

} // namespace lumar
