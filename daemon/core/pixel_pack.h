// Interleaved 8-bit RGB <-> RGBA rows, for the renderer's uploads and readbacks: GL moves
// RGBA8 rows into and out of an RGBA8 framebuffer as they are, where RGB rows take a per-pixel
// conversion inside the driver (Mesa's generic swizzle; on llvmpipe at 1280 x 720 these loops
// plus the plain copies cost ~1.4 ms less per frame than the driver's RGB upload and read).
#pragma once

#include <cstddef>
#include <cstdint>

namespace lumar {

// `pixels` RGB pixels to RGBA with alpha 255. `rgb` and `rgba` must not overlap.
void expandRgbToRgba(const uint8_t* rgb, uint8_t* rgba, size_t pixels);

// `pixels` RGBA pixels to RGB (alpha dropped). `rgba` and `rgb` must not overlap.
void packRgbaToRgb(const uint8_t* rgba, uint8_t* rgb, size_t pixels);

} // namespace lumar
