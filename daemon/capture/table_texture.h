// The fake scene's table-top: a seeded, procedural wood texture (growth-ring grain along x,
// warped, with fibre streaks and slow tint changes), stored once per camera so rendering a
// frame is one texel fetch per ray. In the plain room the lamp's light is baked in; under an
// environment map the texels are the wood's albedo as code values, lit by fake_camera.cpp.
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include "capture/fake_scene_shading.h"

namespace lumar {

// The wood's generators (growth rings, warps, fibres, tint), made from the seed once, so that
// any run of texels can be made on its own: the fake camera under an environment map lights
// the table a row at a time and never holds the albedo whole (16.8 MB at 2048²).
class TableWood {
public:
    explicit TableWood(uint64_t seed);
    ~TableWood();
    TableWood(const TableWood&) = delete;
    TableWood& operator=(const TableWood&) = delete;

    // Texels [tx0, tx1) of row ty into out[0, tx1 - tx0): TableTexture(seed, lamp)'s values.
    void row(int ty, int tx0, int tx1, bool lamp, fake_scene::PackedRgb* out) const;

private:
    struct Generators;
    std::unique_ptr<const Generators> generators_;
};

class TableTexture {
public:
    static constexpr int kResolution = 2048; // texels per side: 0.59 mm each
    static constexpr float kTexelsPerMetre = float(kResolution) / (2.0f * fake_scene::kTableHalfSize);

    // `lamp`: bake in fake_scene::tableLighting (the plain room), else the bare albedo.
    explicit TableTexture(uint64_t seed, bool lamp = true);

    // The texel under table point (x, y), |x|, |y| <= kTableHalfSize (sRGB code values).
    [[nodiscard]] fake_scene::PackedRgb at(float x, float y) const
    {
        const int tx = clampIndex(int((x + fake_scene::kTableHalfSize) * kTexelsPerMetre));
        const int ty = clampIndex(int((y + fake_scene::kTableHalfSize) * kTexelsPerMetre));
        return texels_[size_t(ty) * kResolution + size_t(tx)];
    }

    // Row-major texels, row 0 at y = −kTableHalfSize, for callers that compute indices in bulk.
    [[nodiscard]] const fake_scene::PackedRgb* texels() const { return texels_.data(); }

private:
    static int clampIndex(int i) { return i < 0 ? 0 : (i >= kResolution ? kResolution - 1 : i); }

    std::vector<fake_scene::PackedRgb> texels_;
};

} // namespace lumar
