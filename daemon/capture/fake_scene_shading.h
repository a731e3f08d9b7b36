// What the fake camera's world looks like, in display-referred sRGB code values (0–255).
// The scene is shaded and box-filtered in encoded values rather than linear light: a real
// sensor integrates linear light, but then gamma moves a black/white edge about 0.2 px
// towards the black side, and the fake camera exists to give the tracker unbiased edges.
#pragma once

#include <cstdint>

#include <glm/glm.hpp>

namespace lumar::fake_scene {

// Colours travel packed as integer code values R | G << 10 | B << 20, so adding up the rays
// of one pixel costs one integer add per ray; a 10-bit lane holds the sum of 4 rays.
using PackedRgb = uint32_t;
inline constexpr int kLaneBits = 10;
inline constexpr uint32_t kLaneMask = (1u << kLaneBits) - 1;
inline constexpr int kMaxRaysPerSum = int(kLaneMask / 255);

inline PackedRgb packGrey(float v)
{
    const int i = int(v + 0.5f);
    const uint32_t c = uint32_t(i < 0 ? 0 : (i > 255 ? 255 : i));
    return c | (c << kLaneBits) | (c << (2 * kLaneBits));
}

inline PackedRgb packRgb(const glm::vec3& v)
{
    const auto lane = [](float x) {
        const int i = int(x + 0.5f);
        return uint32_t(i < 0 ? 0 : (i > 255 ? 255 : i));
    };
    return lane(v.x) | (lane(v.y) << kLaneBits) | (lane(v.z) << (2 * kLaneBits));
}

inline constexpr float kTableHalfSize = 0.6f; // the 1.2 m × 1.2 m table-top, centred on 0
inline constexpr float kFloorZ = -0.75f;      // the floor under the table
inline constexpr float kRoomRadius = 3.5f;    // walls beyond this distance from the table

inline constexpr float kInkBlack = 28.0f; // tag print, code values before lighting
inline constexpr float kPaperWhite = 232.0f;

// A soft lamp above the table's centre: 1 at the centre, about 0.85 at the table's corners.
inline float tableLighting(float x, float y)
{
    return 0.78f + 0.22f / (1.0f + (x * x + y * y) * (1.0f / 0.35f));
}

// A dim, untextured floor that fades with the squared distance from below the lamp.
inline glm::vec3 floorColour(float radiusSquared)
{
    const float falloff = 0.55f + 0.45f / (1.0f + radiusSquared * 0.5f);
    return glm::vec3(92.0f, 86.0f, 80.0f) * falloff;
}

// Pale walls, a little brighter towards the ceiling; `upness` is the ray's z over its length.
inline glm::vec3 wallColour(float upness)
{
    return glm::vec3(196.0f, 192.0f, 184.0f) * (0.8f + 0.15f * upness);
}

} // namespace lumar::fake_scene
