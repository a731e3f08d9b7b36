#include "gles_renderer/scene/tile_cover.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace lumar {

TileCover::TileCover(int width, int height, int tile)
    : width_(std::max(width, 1)), height_(std::max(height, 1)), tile_(std::max(tile, 1)),
      columns_((width_ + tile_ - 1) / tile_), rows_((height_ + tile_ - 1) / tile_),
      cells_(size_t(columns_) * size_t(rows_), 0)
{
}

void TileCover::addAll(uint32_t label)
{
    for (uint32_t& cell : cells_)
        cell |= label;
}

void TileCover::markRow(int row, double x0, double x1, uint32_t label)
{
    if (!(x1 >= 0.0 && x0 < double(width_)))
        return;
    const int first = std::clamp(int(std::floor(x0 / tile_)), 0, columns_ - 1);
    const int last = std::clamp(int(std::floor(x1 / tile_)), 0, columns_ - 1);
    for (int column = first; column <= last; ++column)
        cells_[size_t(row * columns_ + column)] |= label;
}

void TileCover::addConvex(std::span<const glm::dvec2> polygon, double margin, uint32_t label)
{
    if (polygon.empty())
        return;
    double yLow = std::numeric_limits<double>::infinity(), yHigh = -yLow;
    for (const glm::dvec2& p : polygon) {
        if (!std::isfinite(p.x) || !std::isfinite(p.y)) {
            addAll(label);
            return;
        }
        yLow = std::min(yLow, p.y);
        yHigh = std::max(yHigh, p.y);
    }
    if (!(yHigh + margin >= 0.0 && yLow - margin < double(height_)))
        return;
    const int firstRow = std::clamp(int(std::floor((yLow - margin) / tile_)), 0, rows_ - 1);
    const int lastRow = std::clamp(int(std::floor((yHigh + margin) / tile_)), 0, rows_ - 1);
    for (int row = firstRow; row <= lastRow; ++row) {
        // The polygon's extent along x within the row's band (grown by the margin): its
        // vertices inside the band and its edges' crossings of the band's two lines.
        const double band0 = double(row * tile_) - margin, band1 = double((row + 1) * tile_) + margin;
        double xLow = std::numeric_limits<double>::infinity(), xHigh = -xLow;
        for (size_t i = 0; i < polygon.size(); ++i) {
            const glm::dvec2& a = polygon[i];
            const glm::dvec2& b = polygon[(i + 1) % polygon.size()];
            if (band0 <= a.y && a.y <= band1) {
                xLow = std::min(xLow, a.x);
                xHigh = std::max(xHigh, a.x);
            }
            for (const double y : {band0, band1})
                if ((a.y - y) * (b.y - y) < 0.0) {
                    const double x = a.x + (y - a.y) / (b.y - a.y) * (b.x - a.x);
                    xLow = std::min(xLow, x);
                    xHigh = std::max(xHigh, x);
                }
        }
        if (xLow <= xHigh)
            markRow(row, xLow - margin, xHigh + margin, label);
    }
}

template <typename Selected> std::vector<PixelRect> TileCover::rectsOf(const Selected& selected) const
{
    RowRunMerger merger;
    for (int row = 0; row < rows_; ++row) {
        const int y0 = row * tile_, y1 = std::min((row + 1) * tile_, height_);
        std::vector<PixelRect> runs;
        for (int column = 0; column < columns_; ++column) {
            if (!selected(label(column, row)))
                continue;
            const int x0 = column * tile_, x1 = std::min((column + 1) * tile_, width_);
            if (!runs.empty() && runs.back().x1 == x0)
                runs.back().x1 = x1;
            else
                runs.push_back({x0, y0, x1, y1});
        }
        merger.addRow(std::move(runs));
    }
    return std::move(merger).finish();
}

std::vector<PixelRect> TileCover::rects() const
{
    return rectsOf([](uint32_t label) { return label != 0; });
}

void TileCover::mergeLabels(int blocks)
{
    blocks = std::max(blocks, 1);
    for (int row0 = 0; row0 < rows_; row0 += blocks)
        for (int column0 = 0; column0 < columns_; column0 += blocks) {
            const int row1 = std::min(row0 + blocks, rows_), column1 = std::min(column0 + blocks, columns_);
            uint32_t merged = 0;
            for (int row = row0; row < row1; ++row)
                for (int column = column0; column < column1; ++column)
                    merged |= label(column, row);
            for (int row = row0; row < row1; ++row)
                for (int column = column0; column < column1; ++column)
                    if (uint32_t& cell = cells_[size_t(row * columns_ + column)]; cell != 0)
                        cell = merged;
        }
}

void TileCover::subtract(const TileCover& other)
{
    if (other.columns_ != columns_ || other.rows_ != rows_)
        return;
    for (size_t i = 0; i < cells_.size(); ++i)
        if (other.cells_[i] != 0)
            cells_[i] = 0;
}

std::vector<TileCover::LabelledRect> TileCover::labelledRects() const
{
    std::vector<uint32_t> labels(cells_);
    std::sort(labels.begin(), labels.end());
    labels.erase(std::unique(labels.begin(), labels.end()), labels.end());
    std::vector<LabelledRect> result;
    for (const uint32_t label : labels)
        if (label != 0)
            for (const PixelRect& rect : rectsOf([label](uint32_t l) { return l == label; }))
                result.push_back({rect, label});
    return result;
}

} // namespace lumar
