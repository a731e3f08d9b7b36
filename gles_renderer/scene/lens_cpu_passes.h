// The lens effects' passes after the bright pass (the bloom pyramid down and up, the glare
// streaks) computed on the CPU, over the texels within reach of the bright light: the path
// LensEffects takes on a software rasteriser (LensCulling). There every pass of the GL
// pyramid is a render pass of its own with a fixed cost, a wait on the one before and its
// sampling in JIT code (RGBM texels fetched one by one); the car scene with bloom on
// llvmpipe spent 1.9 ms of wall time in the eight passes after the bright pass, against
// 1.1 ms for these loops over the same texels and the upload of their results. Computed
// here, they also tell which tiles the composite must draw (LensEffects::reachedTiles),
// a quarter of those within the reach. The arithmetic is lens_downsample.frag's,
// lens_upsample.frag's and lens_glare.frag's in float (the GL path's float images), texel for
// texel.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include <glm/glm.hpp>

#include "core/image.h"
#include "gles_renderer/scene/pixel_rects.h"

namespace lumar {

// Linear RGB radiance of an image `width` x `height` texels, held over `texels` only: every
// texel outside it is 0 (the GL passes' images are cleared, or 0 outside what the culled
// passes read).
class RadianceRegion {
public:
    // Zero over `texels` clipped to the image. Keeps its memory: a region reused every frame
    // allocates only when it outgrows what it held.
    void reset(int width, int height, const PixelRect& texels);

    [[nodiscard]] int width() const { return width_; }
    [[nodiscard]] int height() const { return height_; }
    [[nodiscard]] const PixelRect& texels() const { return texels_; }
    // A texel's radiance; 0 outside the region (and the image).
    [[nodiscard]] glm::vec3 at(int x, int y) const
    {
        if (x < texels_.x0 || x >= texels_.x1 || y < texels_.y0 || y >= texels_.y1)
            return glm::vec3(0.0f);
        const float* p = &rgb_[index(x, y)];
        return {p[0], p[1], p[2]};
    }
    // Row y's texels x0 .. x1 - 1 of the region, RGB interleaved; y within the region.
    [[nodiscard]] float* row(int y) { return &rgb_[index(texels_.x0, y)]; }
    [[nodiscard]] const float* row(int y) const { return &rgb_[index(texels_.x0, y)]; }
    // The bilinear interpolation at `coordinate` (texels, centres at +0.5) clamped to the
    // image's edge: a float texture's textureLod with GL_LINEAR and GL_CLAMP_TO_EDGE.
    [[nodiscard]] glm::vec3 bilinear(glm::vec2 coordinate) const;
    // The whole image, 0 outside the region.
    [[nodiscard]] ImageF image() const;

private:
    [[nodiscard]] size_t index(int x, int y) const
    {
        return (size_t(y - texels_.y0) * size_t(texels_.x1 - texels_.x0) + size_t(x - texels_.x0)) * 3;
    }

    int width_ = 0;
    int height_ = 0;
    PixelRect texels_;
    std::vector<float> rgb_;
};

// lens_downsample.frag past the bright pass (threshold 0): each texel of `level` (its region,
// as reset; only those within `texels` where given) the mean of the 2 x 2 texels of `source`
// under it.
void downsampleRegion(const RadianceRegion& source, RadianceRegion& level);
void downsampleRegion(const RadianceRegion& source, RadianceRegion& level, const PixelRect& texels);

// lens_upsample.frag: each texel of `out` within `texels` (and its region, as reset) is
// `level`'s texel weighted by `weight` plus `coarser` bilinearly doubled, by 1 - weight.
void upsampleRegion(const RadianceRegion& level, const RadianceRegion& coarser, float weight, RadianceRegion& out,
                    const PixelRect& texels);

// lens_glare.frag with float images: each texel of `out` (its region, as reset; only those
// within `texels` where given; the same image size as `source`) gathers `source` from behind
// it along every streak (`steps`: one sample's offset along each, texels) with `weights` by
// sample index, the centre once with all the streaks' weight.
void gatherGlareRegion(const RadianceRegion& source, std::span<const glm::vec2> steps, std::span<const float> weights,
                       RadianceRegion& out);
void gatherGlareRegion(const RadianceRegion& source, std::span<const glm::vec2> steps, std::span<const float> weights,
                       RadianceRegion& out, const PixelRect& texels);

// A GL_R11F_G11F_B10F texel as glReadPixels gives it (GL_UNSIGNED_INT_10F_11F_11F_REV):
// red in bits 0-10, green 11-21, blue 22-31; unsigned floats of 5 exponent bits (bias 15)
// and 6, 6, 5 mantissa bits. Infinity comes back as the channel's largest finite value
// (65024 or 64512), NaN as 0.
[[nodiscard]] glm::vec3 unpackR11G11B10F(uint32_t texel);

} // namespace lumar
