// Which tiles of a viewport a set of convex window-space polygons can touch, as disjoint
// rectangles for the scissor test. ShadowPass shades the real surfaces' darkening only where a
// shadow or a contact can fall: the bounding rectangles of those places on a table covered
// ~87 % of car.toml's frame, the tiles that the places themselves (a shadow's parallelogram, a
// contact's ellipse) touch a small part of it.
#pragma once

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
    // `margin` pixels around it overlaps. A vertex that is not finite marks the whole viewport.
    void addConvex(std::span<const glm::dvec2> polygon, double margin);
    void addAll();

    // Disjoint rectangles, within the viewport, whose union is the marked tiles: the runs of
    // marked tiles along each row, a run with the same span as the one above it continuing that
    // rectangle downwards.
    [[nodiscard]] std::vector<PixelRect> rects() const;

    [[nodiscard]] int columns() const { return columns_; }
    [[nodiscard]] int rows() const { return rows_; }
    [[nodiscard]] bool marked(int column, int row) const { return cells_[size_t(row * columns_ + column)] != 0; }

private:
    void markRow(int row, double x0, double x1);

    int width_, height_, tile_;
    int columns_, rows_;
    std::vector<unsigned char> cells_;
};

} // namespace lumar
