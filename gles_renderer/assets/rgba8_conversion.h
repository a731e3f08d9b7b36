// Decoded texture pixels (1 to 4 interleaved components of 8 or 16 bits, as stb_image and
// tinygltf deliver them) converted to the RGBA8 layout the renderer uploads.
#pragma once

#include <cstdint>
#include <span>

#include "core/image.h"

namespace lumar {

// Grey becomes (g, g, g, 255), grey+alpha (g, g, g, a), RGB gets alpha 255. 16-bit samples
// (native byte order) are rounded to the nearest 8-bit value. Throws InputError (a message
// without a file name; the caller adds it) when the shape is invalid or `pixels` does not
// hold exactly width * height * components samples.
Image8 convertToRgba8(std::span<const uint8_t> pixels, int width, int height, int components, int bitsPerComponent);

} // namespace lumar
