#include "capture/table_texture.h"

#include <algorithm>
#include <cmath>

#include "capture/splitmix64.h"

namespace lumar {
namespace {

float smoothstep(float edge0, float edge1, float x)
{
    const float t = std::clamp((x - edge0) / (edge1 - edge0), 0.0f, 1.0f);
    return t * t * (3.0f - 2.0f * t);
}

// Value noise on a cellsX × cellsY lattice spanning the texture, in [-1, 1]. Lattice
// coordinates and smoothstep weights depend on the column or the row only, so they are
// computed once per axis and every texel costs one bilinear blend.
class LatticeNoise {
public:
    LatticeNoise(int cellsX, int cellsY, SplitMix64& rng)
        : stride_(size_t(cellsX) + 1), values_(stride_ * (size_t(cellsY) + 1)), columns_(axis(cellsX)),
          rows_(axis(cellsY))
    {
        for (float& v : values_) {
            v = float(2.0 * rng.uniform() - 1.0);
        }
    }

    [[nodiscard]] float at(int tx, int ty) const
    {
        const Axis& c = columns_[size_t(tx)];
        const Axis& r = rows_[size_t(ty)];
        const float* row0 = values_.data() + size_t(r.cell) * stride_;
        const float* row1 = row0 + stride_;
        const float top = row0[c.cell] + c.weight * (row0[c.cell + 1] - row0[c.cell]);
        const float bottom = row1[c.cell] + c.weight * (row1[c.cell + 1] - row1[c.cell]);
        return top + r.weight * (bottom - top);
    }

private:
    struct Axis {
        int cell = 0;
        float weight = 0.0f;
    };
    static std::vector<Axis> axis(int cells)
    {
        std::vector<Axis> out(TableTexture::kResolution);
        for (int i = 0; i < TableTexture::kResolution; ++i) {
            const float pos = (float(i) + 0.5f) * float(cells) / float(TableTexture::kResolution);
            const int cell = std::min(int(pos), cells - 1);
            out[size_t(i)] = {cell, smoothstep(0.0f, 1.0f, pos - float(cell))};
        }
        return out;
    }

    size_t stride_;
    std::vector<float> values_;
    std::vector<Axis> columns_;
    std::vector<Axis> rows_;
};

// Growth rings across the grain: darkness (0 early wood .. 1 late wood) along a coordinate
// in metres, sampled finely enough that a texel never skips a ring edge.
class RingProfile {
public:
    static constexpr float kStart = -1.0f; // wider than the table: the warp shifts lookups
    static constexpr float kLength = 2.0f;
    static constexpr int kSamples = 32768;

    explicit RingProfile(SplitMix64& rng) : darkness_(kSamples)
    {
        float ringStart = kStart;
        float ringWidth = 0.0f;
        float ringStrength = 0.0f;
        for (int i = 0; i < kSamples; ++i) {
            const float pos = kStart + kLength * float(i) / float(kSamples);
            while (pos >= ringStart + ringWidth) {
                ringStart += ringWidth;
                // Mostly narrow rings with the odd wide one, as in sawn timber.
                const double w = rng.uniform();
                ringWidth = float(0.002 + 0.008 * w * w);
                ringStrength = float(0.3 + 0.7 * rng.uniform());
            }
            const float f = (pos - ringStart) / ringWidth;
            // Late wood darkens towards the ring's end and ends sharply at the next ring.
            darkness_[size_t(i)] = ringStrength * smoothstep(0.45f, 0.85f, f) * (1.0f - smoothstep(0.93f, 1.0f, f));
        }
    }

    [[nodiscard]] float at(float pos) const
    {
        const int i = std::clamp(int((pos - kStart) * (float(kSamples) / kLength)), 0, kSamples - 1);
        return darkness_[size_t(i)];
    }

private:
    std::vector<float> darkness_;
};

} // namespace

struct TableWood::Generators {
    // Drawn from one stream in this order: the texture depends on it.
    SplitMix64 rng;
    RingProfile rings;
    // Slow bends of the grain (about ±2 cm) and the plank's overall tint.
    LatticeNoise warpCoarse;
    LatticeNoise warpFine;
    LatticeNoise tint;
    LatticeNoise blotches;
    // Fibres: long along the grain (x), thin across it.
    LatticeNoise fibres;

    explicit Generators(uint64_t seed)
        : rng{splitMix64Hash(seed ^ 0x7461626c65ULL)}, // "table": independent of the noise stream
          rings(rng), warpCoarse(5, 4, rng), warpFine(13, 9, rng), tint(4, 4, rng), blotches(19, 23, rng),
          fibres(20, 900, rng)
    {
    }
};

TableWood::TableWood(uint64_t seed) : generators_(std::make_unique<const Generators>(seed)) {}

TableWood::~TableWood() = default;

void TableWood::row(int ty, int tx0, int tx1, bool lamp, fake_scene::PackedRgb* out) const
{
    const Generators& g = *generators_;
    const glm::vec3 early(200.0f, 152.0f, 104.0f);
    const glm::vec3 late(140.0f, 92.0f, 55.0f);
    const float metresPerTexel = 2.0f * fake_scene::kTableHalfSize / float(TableTexture::kResolution);
    const float y = -fake_scene::kTableHalfSize + (float(ty) + 0.5f) * metresPerTexel;
    for (int tx = tx0; tx < tx1; ++tx) {
        const float x = -fake_scene::kTableHalfSize + (float(tx) + 0.5f) * metresPerTexel;
        const float warp = 0.016f * g.warpCoarse.at(tx, ty) + 0.004f * g.warpFine.at(tx, ty) + 0.01f * x * x;
        const float grain = g.rings.at(y + warp);
        const float fibre = g.fibres.at(tx, ty);
        const float mixDark = std::clamp(0.85f * grain + 0.12f * fibre + 0.08f * g.blotches.at(tx, ty), 0.0f, 1.0f);
        const float brightness =
            (1.0f + 0.07f * g.tint.at(tx, ty) + 0.03f * fibre) * (lamp ? fake_scene::tableLighting(x, y) : 1.0f);
        out[tx - tx0] = fake_scene::packRgb((early + mixDark * (late - early)) * brightness);
    }
}

TableTexture::TableTexture(uint64_t seed, bool lamp) : texels_(size_t(kResolution) * kResolution)
{
    const TableWood wood(seed);
    for (int ty = 0; ty < kResolution; ++ty) {
        wood.row(ty, 0, kResolution, lamp, texels_.data() + size_t(ty) * kResolution);
    }
}

} // namespace lumar
