#include "capture/shared_exponent_image.h"

#include <cmath>
#include <cstring>

namespace lumar {
namespace {

bool sameBits(float a, float b)
{
    return std::memcmp(&a, &b, sizeof a) == 0;
}

} // namespace

SharedExponentImage::SharedExponentImage(const ImageF& image, float scale)
    : width_(image.width), height_(image.height), scale_(scale)
{
    for (int e = 0; e < 256; ++e) {
        powers_[size_t(e)] = std::ldexp(1.0f, e - 136);
    }
    const size_t count = size_t(width_) * size_t(height_);
    packed_.resize(count);
    for (size_t i = 0; i < count; ++i) {
        const float* rgb = image.data.data() + 3 * i;
        const float largest = std::max({rgb[0], rgb[1], rgb[2]});
        int exponent = 0; // largest = f · 2^exponent, f in [0.5, 1): its mantissa byte is f · 256
        (void)std::frexp(largest, &exponent);
        const int e = largest > 0.0f ? exponent + 128 : 0;
        uint32_t texel = uint32_t(std::clamp(e, 0, 255)) << 24;
        // Kept only if every channel comes back bit for bit (a negative, a fraction of the
        // mantissa's last bit, an exponent out of range do not).
        bool exact = e >= 0 && e <= 255;
        for (int c = 0; c < 3 && exact; ++c) {
            const float m = std::ldexp(rgb[c], 136 - e);
            const uint32_t mantissa = m >= 0.0f && m <= 255.0f ? uint32_t(m) : 0u;
            exact = sameBits(float(mantissa) * powers_[size_t(e)], rgb[c]); // as at() reads it back
            texel |= mantissa << (8 * c);
        }
        if (!exact) {
            packed_.clear();
            packed_.shrink_to_fit();
            floats_ = image.data;
            return;
        }
        packed_[i] = texel;
    }
}

} // namespace lumar
