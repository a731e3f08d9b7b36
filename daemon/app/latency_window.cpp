#include "latency_window.h"

#include <algorithm>
#include <stdexcept>

namespace lumar {

LatencyWindow::LatencyWindow(size_t frames) : ring_(frames)
{
    if (frames == 0)
        throw std::logic_error("LatencyWindow: holds at least one frame");
    sorted_.reserve(frames);
}

void LatencyWindow::add(double ms)
{
    ring_[next_] = ms;
    next_ = (next_ + 1) % ring_.size();
    count_ = std::min(count_ + 1, ring_.size());
}

std::optional<double> LatencyWindow::percentile(double p) const
{
    if (count_ == 0)
        return std::nullopt;
    sorted_.assign(ring_.begin(), ring_.begin() + std::ptrdiff_t(count_));
    const size_t index = std::min(count_ - 1, size_t(std::clamp(p, 0.0, 1.0) * double(count_ - 1) + 0.5));
    std::nth_element(sorted_.begin(), sorted_.begin() + std::ptrdiff_t(index), sorted_.end());
    return sorted_[index];
}

} // namespace lumar
