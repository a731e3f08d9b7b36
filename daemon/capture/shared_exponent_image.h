// The fake camera's environment map kept for baking its cube's tiles as frames need them,
// in 4 bytes a texel where that is exact instead of 12: three 8-bit mantissas and a shared
// exponent, the form Radiance .hdr files store, so a map decoded from one fits bit for bit
// (issue 18: the 1k map's floats held 6.3 MB for the camera's lifetime, now 2.1 MB). A map
// that does not fit (another source, an unnormalised file) is kept as its floats.
#pragma once

#include <algorithm>
#include <array>
#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

#include "core/image.h"

namespace lumar {

class SharedExponentImage {
public:
    // `image`: 3 channels. Reads give max(v, 0) · scale for each channel value v.
    SharedExponentImage(const ImageF& image, float scale);

    [[nodiscard]] int width() const { return width_; }
    [[nodiscard]] int height() const { return height_; }
    // Whether the texels fitted the 4-byte form.
    [[nodiscard]] bool compact() const { return !packed_.empty() || floats_.empty(); }

    [[nodiscard]] glm::vec3 at(int x, int y) const
    {
        const size_t i = size_t(y) * size_t(width_) + size_t(x);
        glm::vec3 v;
        if (!packed_.empty()) {
            const uint32_t t = packed_[i];
            const float s = powers_[t >> 24];
            v = glm::vec3(float(t & 0xffu) * s, float((t >> 8) & 0xffu) * s, float((t >> 16) & 0xffu) * s);
        } else {
            v = glm::vec3(floats_[3 * i], floats_[3 * i + 1], floats_[3 * i + 2]);
        }
        return glm::vec3(std::max(v.x, 0.0f) * scale_, std::max(v.y, 0.0f) * scale_, std::max(v.z, 0.0f) * scale_);
    }

private:
    int width_ = 0;
    int height_ = 0;
    float scale_ = 1.0f;
    std::array<float, 256> powers_{}; // exponent byte e -> 2^(e - 136), as Radiance's RGBE
    std::vector<uint32_t> packed_;    // r | g << 8 | b << 16 | e << 24
    std::vector<float> floats_;       // when the texels do not fit
};

} // namespace lumar
