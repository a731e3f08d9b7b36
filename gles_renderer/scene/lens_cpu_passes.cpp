#include "gles_renderer/scene/lens_cpu_passes.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <vector>

namespace lumar {
namespace {

// GL_R11F_G11F_B10F's small unsigned floats (5 exponent bits, bias 15; 6 or 5 mantissa
// bits): a float's bits, or the denormals scaled; infinity as the largest finite value,
// NaN as 0.
float unpackSmallFloat(uint32_t bits, int mantissaBits)
{
    const uint32_t exponent = bits >> mantissaBits, mantissa = bits & ((1u << mantissaBits) - 1u);
    if (exponent == 0)
        return std::ldexp(float(mantissa), -14 - mantissaBits);
    if (exponent == 31)
        return mantissa == 0 ? std::ldexp(2.0f - std::ldexp(1.0f, -mantissaBits), 15) : 0.0f;
    return std::bit_cast<float>(((exponent + 112u) << 23) | (mantissa << (23 - mantissaBits)));
}

} // namespace

glm::vec3 unpackR11G11B10F(uint32_t texel)
{
    return {unpackSmallFloat(texel & 0x7ffu, 6), unpackSmallFloat((texel >> 11) & 0x7ffu, 6),
            unpackSmallFloat(texel >> 22, 5)};
}

void RadianceRegion::reset(int width, int height, const PixelRect& texels)
{
    width_ = width;
    height_ = height;
    texels_ = intersection(texels, {0, 0, width, height});
    if (texels_.empty())
        texels_ = {};
    rgb_.assign(size_t(texels_.area()) * 3, 0.0f);
}

glm::vec3 RadianceRegion::bilinear(glm::vec2 coordinate) const
{
    const glm::vec2 t = coordinate - 0.5f;
    const glm::vec2 floored = glm::floor(t);
    const glm::vec2 f = t - floored;
    const int x = int(floored.x), y = int(floored.y);
    const int xa = std::clamp(x, 0, width_ - 1), xb = std::clamp(x + 1, 0, width_ - 1);
    const int ya = std::clamp(y, 0, height_ - 1), yb = std::clamp(y + 1, 0, height_ - 1);
    return glm::mix(glm::mix(at(xa, ya), at(xb, ya), f.x), glm::mix(at(xa, yb), at(xb, yb), f.x), f.y);
}

ImageF RadianceRegion::image() const
{
    ImageF image(width_, height_, 3);
    for (int y = texels_.y0; y < texels_.y1; ++y)
        std::copy_n(row(y), size_t(texels_.x1 - texels_.x0) * 3, &image.at(texels_.x0, y)[0]);
    return image;
}

void downsampleRegion(const RadianceRegion& source, RadianceRegion& level)
{
    downsampleRegion(source, level, level.texels());
}

void downsampleRegion(const RadianceRegion& source, RadianceRegion& level, const PixelRect& within)
{
    const PixelRect texels = intersection(within, level.texels());
    if (texels.empty())
        return;
    for (int y = texels.y0; y < texels.y1; ++y) {
        float* out = level.row(y) + size_t(texels.x0 - level.texels().x0) * 3;
        for (int x = texels.x0; x < texels.x1; ++x, out += 3) {
            const glm::vec3 sum = source.at(2 * x, 2 * y) + source.at(2 * x + 1, 2 * y) + source.at(2 * x, 2 * y + 1) +
                                  source.at(2 * x + 1, 2 * y + 1);
            out[0] = 0.25f * sum.r;
            out[1] = 0.25f * sum.g;
            out[2] = 0.25f * sum.b;
        }
    }
}

void upsampleRegion(const RadianceRegion& level, const RadianceRegion& coarser, float weight, RadianceRegion& out,
                    const PixelRect& within)
{
    const PixelRect texels = intersection(within, out.texels());
    if (texels.empty())
        return;
    // Doubling bilinearly samples the coarser image at x / 2 - 0.25 (texel centres at +0.5):
    // an even texel 2i weighs coarse texels i - 1 and i by 1/4 and 3/4, an odd one 2i + 1
    // texels i and i + 1 by 3/4 and 1/4, clamped to the image's edge. Separably: each row
    // first blends its two coarse rows, then the blend's neighbours.
    const int coarseX0 = std::max(texels.x0 / 2 - 1, 0), coarseX1 = std::min((texels.x1 + 1) / 2 + 1, coarser.width());
    // Kept between calls: no allocation per frame once the regions stop growing.
    thread_local std::vector<glm::vec3> blended;
    blended.resize(size_t(coarseX1 - coarseX0));
    const auto clampX = [&](int x) { return std::clamp(x, 0, coarser.width() - 1) - coarseX0; };
    for (int y = texels.y0; y < texels.y1; ++y) {
        const int below = y % 2 == 0 ? y / 2 - 1 : y / 2;
        const float fy = y % 2 == 0 ? 0.75f : 0.25f;
        const int ya = std::clamp(below, 0, coarser.height() - 1), yb = std::clamp(below + 1, 0, coarser.height() - 1);
        for (int x = coarseX0; x < coarseX1; ++x)
            blended[size_t(x - coarseX0)] = glm::mix(coarser.at(x, ya), coarser.at(x, yb), fy);
        float* o = out.row(y) + size_t(texels.x0 - out.texels().x0) * 3;
        for (int x = texels.x0; x < texels.x1; ++x, o += 3) {
            const int left = x % 2 == 0 ? x / 2 - 1 : x / 2;
            const float fx = x % 2 == 0 ? 0.75f : 0.25f;
            const glm::vec3 c = glm::mix(blended[size_t(clampX(left))], blended[size_t(clampX(left + 1))], fx);
            const glm::vec3 mixed = glm::mix(c, level.at(x, y), weight);
            o[0] = mixed.r;
            o[1] = mixed.g;
            o[2] = mixed.b;
        }
    }
}

void gatherGlareRegion(const RadianceRegion& source, std::span<const glm::vec2> steps, std::span<const float> weights,
                       RadianceRegion& out)
{
    gatherGlareRegion(source, steps, weights, out, out.texels());
}

void gatherGlareRegion(const RadianceRegion& source, std::span<const glm::vec2> steps, std::span<const float> weights,
                       RadianceRegion& out, const PixelRect& within)
{
    const PixelRect texels = intersection(within, out.texels());
    if (texels.empty())
        return;
    const float centreWeight = float(steps.size()) * weights[0];
    for (int y = texels.y0; y < texels.y1; ++y) {
        float* o = out.row(y) + size_t(texels.x0 - out.texels().x0) * 3;
        for (int x = texels.x0; x < texels.x1; ++x, o += 3) {
            const glm::vec2 p(float(x) + 0.5f, float(y) + 0.5f);
            glm::vec3 sum = centreWeight * source.at(x, y);
            for (const glm::vec2 step : steps)
                for (size_t i = 1; i < weights.size(); ++i)
                    sum += weights[i] * source.bilinear(p - step * float(i));
            o[0] = sum.r;
            o[1] = sum.g;
            o[2] = sum.b;
        }
    }
}

} // namespace lumar
