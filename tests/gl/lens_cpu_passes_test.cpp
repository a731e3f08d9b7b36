// The lens effects' CPU passes (gles_renderer/scene/lens_cpu_passes.h) against their
// definitions written plainly: the separable upsample equals the bilinear doubling texel by
// texel up to the image's edges, the downsample is the mean of four, the glare carries the
// bright light's energy along its rays, and R11F_G11F_B10F texels decode to their values.
#include <cmath>
#include <numbers>
#include <vector>

#include <gtest/gtest.h>

#include "gles_renderer/scene/lens_cpu_passes.h"

namespace lumar {
namespace {

// A region of `texels` in an image `width` x `height` filled with distinct values.
RadianceRegion filledRegion(int width, int height, const PixelRect& texels, float seed)
{
    RadianceRegion region;
    region.reset(width, height, texels);
    const PixelRect& held = region.texels();
    for (int y = held.y0; y < held.y1; ++y) {
        float* row = region.row(y);
        for (int x = held.x0; x < held.x1; ++x)
            for (int c = 0; c < 3; ++c)
                *row++ = std::fmod(seed + 0.37f * float(x) + 0.61f * float(y) + 0.23f * float(c), 3.0f);
    }
    return region;
}

TEST(LensCpuPasses, TheUpsampleIsTheBilinearDoublingUpToTheEdges)
{
    // The coarser image's region stops short of its right edge and starts at its top one:
    // texels outside read 0, and reads past the image clamp to its edge.
    const RadianceRegion coarser = filledRegion(9, 7, {0, 0, 7, 7}, 0.5f);
    const RadianceRegion level = filledRegion(17, 13, {1, 0, 17, 13}, 1.5f);
    RadianceRegion out;
    out.reset(17, 13, {0, 0, 17, 13});
    constexpr float kWeight = 0.25f;
    upsampleRegion(level, coarser, kWeight, out, {0, 0, 17, 13});
    for (int y = 0; y < 13; ++y)
        for (int x = 0; x < 17; ++x) {
            const glm::vec3 expected =
                glm::mix(coarser.bilinear(glm::vec2(float(x) + 0.5f, float(y) + 0.5f) * 0.5f), level.at(x, y), kWeight);
            const glm::vec3 got = out.at(x, y);
            for (int c = 0; c < 3; ++c)
                ASSERT_NEAR(got[c], expected[c], 1e-5f) << x << "," << y << " channel " << c;
        }
}

TEST(LensCpuPasses, TheUpsampleWritesOnlyWithinTheTexelsAsked)
{
    const RadianceRegion coarser = filledRegion(8, 8, {0, 0, 8, 8}, 0.1f);
    const RadianceRegion level = filledRegion(16, 16, {0, 0, 16, 16}, 0.2f);
    RadianceRegion out;
    out.reset(16, 16, {2, 2, 14, 14});
    upsampleRegion(level, coarser, 0.5f, out, {4, 5, 9, 7});
    for (int y = 0; y < 16; ++y)
        for (int x = 0; x < 16; ++x) {
            const bool asked = x >= 4 && x < 9 && y >= 5 && y < 7;
            EXPECT_EQ(out.at(x, y) != glm::vec3(0.0f), asked) << x << "," << y;
        }
}

TEST(LensCpuPasses, TheDownsampleIsTheMeanOfFourWithZeroOutside)
{
    const RadianceRegion source = filledRegion(11, 9, {2, 1, 11, 9}, 0.7f);
    RadianceRegion level;
    level.reset(6, 5, {0, 0, 6, 5});
    downsampleRegion(source, level);
    for (int y = 0; y < 5; ++y)
        for (int x = 0; x < 6; ++x) {
            const glm::vec3 expected = 0.25f * (source.at(2 * x, 2 * y) + source.at(2 * x + 1, 2 * y) +
                                                source.at(2 * x, 2 * y + 1) + source.at(2 * x + 1, 2 * y + 1));
            EXPECT_LT(glm::length(level.at(x, y) - expected), 1e-6f) << x << "," << y;
        }
}

// One bright texel, four streaks along the axes: the glare keeps its energy and puts it on the
// texels along the rays, none off them.
TEST(LensCpuPasses, TheGlareCarriesTheBrightTexelAlongItsRays)
{
    RadianceRegion source;
    source.reset(32, 32, {0, 0, 32, 32});
    float* spot = source.row(16) + 16 * 3;
    spot[0] = spot[1] = spot[2] = 8.0f;
    const std::vector<glm::vec2> steps{{1, 0}, {0, 1}, {-1, 0}, {0, -1}};
    std::vector<float> weights(6);
    double total = 0.0;
    for (size_t i = 0; i < weights.size(); ++i) {
        weights[i] = std::exp(-0.5f * float(i));
        total += weights[i] * double(steps.size());
    }
    for (float& weight : weights)
        weight = float(weight / total);
    RadianceRegion glare;
    glare.reset(32, 32, {0, 0, 32, 32});
    gatherGlareRegion(source, steps, weights, glare);
    double energy = 0.0, offRays = 0.0;
    for (int y = 0; y < 32; ++y)
        for (int x = 0; x < 32; ++x) {
            energy += glare.at(x, y).r;
            if (x != 16 && y != 16)
                offRays += glare.at(x, y).r;
        }
    EXPECT_NEAR(energy, 8.0, 1e-4);
    EXPECT_EQ(offRays, 0.0);
    EXPECT_GT(glare.at(20, 16).r, 0.0f); // along +x: light moves along the step
    EXPECT_GT(glare.at(16, 20).r, 0.0f);
}

// Encodings from the format's definition (OpenGL ES 3.0 §2.1.3): 1.0 has exponent 15 and a
// zero mantissa; the largest finite values, the smallest denormal, infinity and NaN.
// LensEffects splits each pass in bands of texels (rows, or any rectangle) across two threads:
// a pass over its bands writes what the pass over the whole region writes, texel for texel.
TEST(LensCpuPasses, EachPassOverBandsWritesWhatItWritesOverTheWhole)
{
    const RadianceRegion source = filledRegion(40, 30, {3, 2, 37, 29}, 0.25f);
    const PixelRect texels{2, 1, 18, 15}; // of the half-size images
    const std::vector<PixelRect> bands{{2, 1, 18, 6}, {2, 6, 9, 15}, {9, 6, 18, 15}};
    const auto expectSame = [](const RadianceRegion& a, const RadianceRegion& b) {
        ASSERT_EQ(a.texels().x0, b.texels().x0);
        ASSERT_EQ(a.texels().y1, b.texels().y1);
        const PixelRect& t = a.texels();
        for (int y = t.y0; y < t.y1; ++y)
            for (int i = 0; i < 3 * (t.x1 - t.x0); ++i)
                ASSERT_EQ(a.row(y)[i], b.row(y)[i]) << "row " << y << " value " << i;
    };
    RadianceRegion whole, banded;
    whole.reset(20, 15, texels);
    banded.reset(20, 15, texels);
    downsampleRegion(source, whole);
    for (const PixelRect& band : bands)
        downsampleRegion(source, banded, band);
    expectSame(whole, banded);

    const glm::vec2 steps[] = {{1.0f, 0.0f}, {0.5f, 0.8f}};
    const float weights[] = {0.4f, 0.2f, 0.1f};
    RadianceRegion glareWhole, glareBanded;
    glareWhole.reset(20, 15, texels);
    glareBanded.reset(20, 15, texels);
    gatherGlareRegion(whole, steps, weights, glareWhole);
    for (const PixelRect& band : bands)
        gatherGlareRegion(whole, steps, weights, glareBanded, band);
    expectSame(glareWhole, glareBanded);

    const RadianceRegion coarser = filledRegion(10, 8, {0, 0, 10, 8}, 2.0f);
    RadianceRegion upWhole, upBanded;
    upWhole.reset(20, 15, texels);
    upBanded.reset(20, 15, texels);
    upsampleRegion(whole, coarser, 0.5f, upWhole, texels);
    for (const PixelRect& band : bands)
        upsampleRegion(whole, coarser, 0.5f, upBanded, band);
    expectSame(upWhole, upBanded);
}

TEST(LensCpuPasses, R11G11B10TexelsDecodeToTheirValues)
{
    const auto texel = [](uint32_t r, uint32_t g, uint32_t b) { return r | (g << 11) | (b << 22); };
    EXPECT_EQ(unpackR11G11B10F(0), glm::vec3(0.0f));
    EXPECT_EQ(unpackR11G11B10F(texel(15u << 6, 16u << 6, 14u << 5)), glm::vec3(1.0f, 2.0f, 0.5f));
    EXPECT_EQ(unpackR11G11B10F(texel((15u << 6) | 32u, 0, (15u << 5) | 16u)), glm::vec3(1.5f, 0.0f, 1.5f));
    EXPECT_EQ(unpackR11G11B10F(texel((30u << 6) | 63u, 0, (30u << 5) | 31u)), glm::vec3(65024.0f, 0.0f, 64512.0f));
    EXPECT_EQ(unpackR11G11B10F(texel(1u, 0, 1u)), glm::vec3(std::ldexp(1.0f, -20), 0.0f, std::ldexp(1.0f, -19)));
    EXPECT_EQ(unpackR11G11B10F(texel(31u << 6, (31u << 6) | 1u, 0)), glm::vec3(65024.0f, 0.0f, 0.0f));
}

} // namespace
} // namespace lumar
