// Seeded Gaussian sensor noise that is cheap enough for every pixel of a 30 fps stream: a
// table of Gaussian quantiles indexed by 12-bit slices of SplitMix64 output. Each image
// row has its own generator seeded from (seed, frame, row), so any frame can be rendered
// alone, in any order, and come out identical.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>

#include "capture/splitmix64.h"

namespace lumar {

class SensorNoise {
public:
    static constexpr int kTableBits = 12;

    explicit SensorNoise(double sigma); // sigma in code values; 0 gives no noise

    [[nodiscard]] static SplitMix64 rowGenerator(uint64_t seed, uint64_t sequence, int row)
    {
        const uint64_t frame = splitMix64Hash(seed ^ splitMix64Hash(sequence + 0x6e6f697365ULL));
        return SplitMix64{splitMix64Hash(frame + uint64_t(row) * 0x9e3779b97f4a7c15ULL)};
    }

    // Three independent samples (one per colour channel) from one 64-bit draw.
    void sampleRgb(SplitMix64& rng, float& r, float& g, float& b) const
    {
        const uint64_t bits = rng.next();
        r = table_[(bits >> 16) & kMask];
        g = table_[(bits >> 28) & kMask];
        b = table_[(bits >> 40) & kMask];
    }

    [[nodiscard]] double sigma() const { return sigma_; }

private:
    static constexpr uint64_t kMask = (uint64_t(1) << kTableBits) - 1;
    double sigma_;
    std::array<float, std::size_t(1) << kTableBits> table_{};
};

} // namespace lumar
