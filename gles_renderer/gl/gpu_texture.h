// 2D colour textures for materials: RGBA8 (sRGB-decoding where the data is sRGB-encoded),
// fully mipmapped and sampled trilinearly; and depth textures read by comparison.
#pragma once

#include <cstdint>
#include <utility>

#include "core/image.h"
#include "gles_renderer/gl/gl_object.h"

namespace lumar {

// Number of mip levels of a full chain down to 1x1.
int mipLevelCount(int width, int height);

// The size a width x height texture is uploaded at when its larger side may be at most
// `maxSize` (0: no limit): scaled down keeping its aspect ratio, each side at least 1.
std::pair<int, int> cappedTextureSize(int width, int height, int maxSize);

// A 4-channel image scaled down to width x height for a texture sampled with repeat wrapping:
// filtered in linear light when `srgb` (alpha as coverage), else channel by channel.
Image8 downscaleTexture(const Image8& rgba, int width, int height, bool srgb);

// Uploads a 4-channel image (row 0 = texture coordinate t = 0, glTF's uv (0, 0)) with
// mipmaps, trilinear filtering and repeat wrapping. The caller checks the shape. An image
// larger than `maxSize` (0: no limit) is scaled down to fit first (cappedTextureSize).
GlTexture uploadMaterialTexture(const Image8& rgba, bool srgb, int maxSize = 0);

// A 1x1 texture of one texel, for materials without that texture.
GlTexture makeSolidTexture(uint8_t r, uint8_t g, uint8_t b, uint8_t a);

// A one-level texture a pass renders into and a later one reads: `format` (e.g. GL_R8,
// GL_RGBA16F), `filter` (GL_NEAREST or GL_LINEAR) for both minification and magnification,
// wrapping `wrapS` horizontally and clamped vertically. Left bound to GL_TEXTURE_2D.
GlTexture makeRenderTexture(GLenum format, int width, int height, GLenum filter, GLenum wrapS = GL_CLAMP_TO_EDGE);

// A 24-bit depth texture read by comparison (a sampler2DShadow: texture() returns the share
// of the 2 x 2 nearest texels whose depth is >= the reference, bilinearly weighted), clamped
// at its edges: shadow maps, and the phantoms' depth as the camera sees them. With `stencil`,
// DEPTH24_STENCIL8 (the shadow map's stencil holds its dither pattern).
GlTexture makeDepthCompareTexture(int width, int height, bool stencil = false);

} // namespace lumar
