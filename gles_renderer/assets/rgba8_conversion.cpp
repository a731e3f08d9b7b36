#include "gles_renderer/assets/rgba8_conversion.h"

#include <cstring>
#include <string>

#include "core/error.h"

namespace lumar {
namespace {

// The 8-bit value nearest to a 16-bit one: round(v * 255 / 65535).
uint8_t to8Bit(uint16_t v)
{
    return uint8_t((uint32_t(v) * 255u + 32767u) / 65535u);
}

} // namespace

Image8 convertToRgba8(std::span<const uint8_t> pixels, int width, int height, int components, int bitsPerComponent)
{
    if (width <= 0 || height <= 0) {
        throw InputError("invalid image size " + std::to_string(width) + "x" + std::to_string(height));
    }
    if (components < 1 || components > 4) {
        throw InputError("unsupported image with " + std::to_string(components) + " components");
    }
    if (bitsPerComponent != 8 && bitsPerComponent != 16) {
        throw InputError("unsupported image with " + std::to_string(bitsPerComponent) + " bits per component");
    }
    const size_t bytesPerSample = size_t(bitsPerComponent / 8);
    const size_t samples = size_t(width) * size_t(height) * size_t(components);
    if (pixels.size() != samples * bytesPerSample) {
        throw InputError("decoded image holds " + std::to_string(pixels.size()) + " bytes, expected " +
                         std::to_string(samples * bytesPerSample));
    }

    auto sample = [&](size_t index) -> uint8_t {
        if (bytesPerSample == 1) {
            return pixels[index];
        }
        uint16_t value = 0;
        std::memcpy(&value, pixels.data() + index * 2, 2);
        return to8Bit(value);
    };

    Image8 rgba(width, height, 4);
    const size_t pixelCount = size_t(width) * size_t(height);
    for (size_t p = 0; p < pixelCount; ++p) {
        const size_t in = p * size_t(components);
        uint8_t* out = rgba.data.data() + p * 4;
        if (components <= 2) {
            const uint8_t grey = sample(in);
            out[0] = out[1] = out[2] = grey;
            out[3] = components == 2 ? sample(in + 1) : uint8_t(255);
        } else {
            out[0] = sample(in);
            out[1] = sample(in + 1);
            out[2] = sample(in + 2);
            out[3] = components == 4 ? sample(in + 3) : uint8_t(255);
        }
    }
    return rgba;
}

} // namespace lumar
