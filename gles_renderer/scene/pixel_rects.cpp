#include "gles_renderer/scene/pixel_rects.h"

#include <algorithm>

namespace lumar {

std::vector<PixelRect> disjointCover(std::span<const PixelRect> rects)
{
    std::vector<int> xs, ys;
    for (const PixelRect& r : rects)
        if (!r.empty()) {
            xs.insert(xs.end(), {r.x0, r.x1});
            ys.insert(ys.end(), {r.y0, r.y1});
        }
    std::sort(xs.begin(), xs.end());
    xs.erase(std::unique(xs.begin(), xs.end()), xs.end());
    std::sort(ys.begin(), ys.end());
    ys.erase(std::unique(ys.begin(), ys.end()), ys.end());
    const auto covered = [&](int x0, int y0) {
        return std::any_of(rects.begin(), rects.end(), [&](const PixelRect& r) {
            return !r.empty() && r.x0 <= x0 && x0 < r.x1 && r.y0 <= y0 && y0 < r.y1;
        });
    };
    RowRunMerger merger;
    for (size_t j = 0; j + 1 < ys.size(); ++j) {
        std::vector<PixelRect> row;
        for (size_t i = 0; i + 1 < xs.size(); ++i) {
            if (!covered(xs[i], ys[j]))
                continue;
            if (!row.empty() && row.back().x1 == xs[i])
                row.back().x1 = xs[i + 1];
            else
                row.push_back({xs[i], ys[j], xs[i + 1], ys[j + 1]});
        }
        merger.addRow(std::move(row));
    }
    return std::move(merger).finish();
}

void RowRunMerger::addRow(std::vector<PixelRect> runs)
{
    for (PixelRect& run : runs)
        for (PixelRect& above : previousRow_)
            if (above.x0 == run.x0 && above.x1 == run.x1 && above.y1 == run.y0) {
                run.y0 = above.y0;
                above = PixelRect{}; // taken over
            }
    for (const PixelRect& above : previousRow_)
        if (!above.empty())
            cover_.push_back(above);
    previousRow_ = std::move(runs);
}

std::vector<PixelRect> RowRunMerger::finish() &&
{
    cover_.insert(cover_.end(), previousRow_.begin(), previousRow_.end());
    return std::move(cover_);
}

} // namespace lumar
