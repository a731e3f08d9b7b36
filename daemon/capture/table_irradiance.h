// The light on the fake table under an environment map, as the radiance of a white table:
// W(x, y) = E(x, y) / π, with E the map's irradiance for the up normal (its SH, as the
// renderer lights virtual objects) less what the fake objects standing on the table block.
//
// The blocked part is estimated with a few hundred directions drawn from the map's upper
// hemisphere in proportion to radiance × cos: the sun gets most of them (a sharp-ish shadow),
// the sky the rest (the soft darkening where an object meets the table). Each direction's
// shadow is the object's outline projected along it onto the table, rasterised into a grid.
#pragma once

#include <algorithm>
#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

#include "capture/fake_objects.h"
#include "capture/fake_scene_shading.h"
#include "core/image.h"

namespace lumar {

struct LightSample {
    glm::vec3 direction{0.0f, 0.0f, 1.0f}; // world, unit, z > 0
    glm::vec3 irradiance{0.0f};            // its share of the unoccluded up irradiance
};

// `count` directions drawn from the upper hemisphere of `equirect` (linear radiance,
// environment_map.h's layout) with probability ∝ luminance × cos, stratified and
// deterministic. Their irradiance sums to the map's up irradiance (estimated).
std::vector<LightSample> skyLightSamples(const ImageF& equirect, int count);

class TableIrradiance {
public:
    static constexpr int kCells = 600; // per side: 2 mm cells over the 1.2 m table
    static constexpr float kCellsPerMetre = float(kCells) / (2.0f * fake_scene::kTableHalfSize);

    // `unoccluded`: W with nothing on the table; `equirect`: the map (intensity applied).
    TableIrradiance(const glm::vec3& unoccluded, const ImageF& equirect, const std::vector<FakeObject>& objects);

    [[nodiscard]] const glm::vec3& unoccluded() const { return unoccluded_; }

    // Whether W may differ from unoccluded() near table point (x, y) (any of the four cells
    // at() blends). Off the table: false.
    [[nodiscard]] bool shadowed(float x, float y) const
    {
        if (quadShadowed_.empty()) {
            return false;
        }
        const Cell c = cell(x, y);
        return quadShadowed_[size_t(c.j * kCells + c.i)] != 0;
    }

    // W at table point (x, y), bilinear between cell centres.
    [[nodiscard]] glm::vec3 at(float x, float y) const;

private:
    struct Cell {
        int i = 0; // lower-left cell of the four blended
        int j = 0;
        float fx = 0.0f;
        float fy = 0.0f;
    };
    [[nodiscard]] static Cell cell(float x, float y)
    {
        const float gx = std::clamp((x + fake_scene::kTableHalfSize) * kCellsPerMetre - 0.5f, 0.0f, float(kCells - 1));
        const float gy = std::clamp((y + fake_scene::kTableHalfSize) * kCellsPerMetre - 0.5f, 0.0f, float(kCells - 1));
        Cell c;
        c.i = std::min(int(gx), kCells - 2);
        c.j = std::min(int(gy), kCells - 2);
        c.fx = gx - float(c.i);
        c.fy = gy - float(c.j);
        return c;
    }

    glm::vec3 unoccluded_;
    std::vector<glm::vec3> cells_;      // W per cell; empty when nothing is shadowed
    std::vector<uint8_t> quadShadowed_; // per lower-left cell: any of its four shadowed
};

} // namespace lumar
