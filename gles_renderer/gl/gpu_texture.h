// 2D colour textures for materials: RGBA8 (sRGB-decoding where the data is sRGB-encoded),
// fully mipmapped and sampled trilinearly; and depth textures read by comparison.
#pragma once

#include <cstdint>

#include "core/image.h"
#include "gles_renderer/gl/gl_object.h"

namespace lumar {

// Number of mip levels of a full chain down to 1x1.
int mipLevelCount(int width, int height);

// Uploads a 4-channel image (row 0 = texture coordinate t = 0, glTF's uv (0, 0)) with
// mipmaps, trilinear filtering and repeat wrapping. The caller checks the shape.
GlTexture uploadMaterialTexture(const Image8& rgba, bool srgb);

// A 1x1 texture of one texel, for materials without that texture.
GlTexture makeSolidTexture(uint8_t r, uint8_t g, uint8_t b, uint8_t a);

// A 24-bit depth texture read by comparison (a sampler2DShadow: texture() returns the share
// of the 2 x 2 nearest texels whose depth is >= the reference, bilinearly weighted), clamped
// at its edges: shadow maps, and the phantoms' depth as the camera sees them.
GlTexture makeDepthCompareTexture(int width, int height);

} // namespace lumar
