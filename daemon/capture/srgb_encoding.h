// The fake camera's response curve: linear radiance (already multiplied by the exposure) to
// sRGB code values, code = 255 · sRGB_encode(clamp(L, 0, 1)), by table, so per-ray shading
// costs a multiply and a lookup per channel instead of a pow().
#pragma once

#include <array>
#include <cmath>
#include <cstdint>

#include <glm/glm.hpp>

#include "capture/fake_scene_shading.h"

namespace lumar {

// The exact sRGB transfer functions, on [0, 1].
inline double srgbEncode(double linear)
{
    return linear <= 0.0031308 ? 12.92 * linear : 1.055 * std::pow(linear, 1.0 / 2.4) - 0.055;
}

inline double srgbDecode(double encoded)
{
    return encoded <= 0.04045 ? encoded / 12.92 : std::pow((encoded + 0.055) / 1.055, 2.4);
}

class SrgbEncoder {
public:
    // 16384 steps: at the dark end, where the curve is steepest (12.92 · 255 codes per unit),
    // one step is 0.2 code values, so the table rounds like the exact curve to within that.
    static constexpr int kSteps = 16384;

    SrgbEncoder()
    {
        for (int i = 0; i < kSteps; ++i) {
            codes_[size_t(i)] = uint8_t(std::lround(255.0 * srgbEncode(double(i) / (kSteps - 1))));
        }
        for (int c = 0; c < 256; ++c) {
            linear_[size_t(c)] = float(srgbDecode(c / 255.0));
        }
    }

    // The code value of linear radiance `v` (clamped to [0, 1]; NaN gives 0).
    [[nodiscard]] uint32_t code(float v) const
    {
        const float scaled = v * float(kSteps - 1) + 0.5f;
        const float clamped = scaled > 0.0f ? (scaled < float(kSteps - 1) ? scaled : float(kSteps - 1)) : 0.0f;
        return codes_[size_t(clamped)];
    }

    [[nodiscard]] fake_scene::PackedRgb pack(const glm::vec3& v) const
    {
        return code(v.x) | (code(v.y) << fake_scene::kLaneBits) | (code(v.z) << (2 * fake_scene::kLaneBits));
    }

    // The linear value of code value c (0..255): the albedo a texel's code stands for.
    [[nodiscard]] float linear(uint32_t c) const { return linear_[c]; }

    [[nodiscard]] glm::vec3 unpackLinear(fake_scene::PackedRgb p) const
    {
        return {linear_[p & fake_scene::kLaneMask], linear_[(p >> fake_scene::kLaneBits) & fake_scene::kLaneMask],
                linear_[p >> (2 * fake_scene::kLaneBits)]};
    }

private:
    std::array<uint8_t, kSteps> codes_{};
    std::array<float, 256> linear_{};
};

} // namespace lumar
