// The capture-to-present latencies of the latest frames (FrameReport::latencyMs), for
// status.json's p50 and p99: a fixed ring, so adding a frame's figure never allocates.
#pragma once

#include <cstddef>
#include <optional>
#include <vector>

namespace lumar {

class LatencyWindow {
public:
    explicit LatencyWindow(size_t frames = 128);
    void add(double ms);
    // The p-quantile (0..1, nearest rank) of the frames held; nullopt before the first.
    [[nodiscard]] std::optional<double> percentile(double p) const;
    [[nodiscard]] size_t size() const { return count_; }

private:
    std::vector<double> ring_;
    size_t next_ = 0, count_ = 0;
    mutable std::vector<double> sorted_; // scratch, sized once
};

} // namespace lumar
