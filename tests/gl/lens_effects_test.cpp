// Lens effects (gles_renderer/scene/lens_effects.h), measured: the bloom keeps the bright
// light's energy and spreads it over a stated radius, nothing below the threshold blooms, glare
// streaks run along the configured rays, and with no virtual object every effect leaves the
// camera image as it was. Each with RGBA16F images and with the RGBA8 RGBM fallback, on GL over
// the whole frame and culled (the pyramid and the glare on the CPU near the bright light),
// which gives the frame the whole-frame effects give.
#include <cmath>
#include <initializer_list>
#include <numbers>
#include <optional>
#include <string>
#include <tuple>
#include <vector>

#include <gtest/gtest.h>

#include "gl_test_support.h"
#include "gles_renderer/gl/egl_context.h"
#include "gles_renderer/gl/render_target.h"
#include "gles_renderer/scene/lens_effects.h"

namespace lumar {
namespace {

constexpr int kSize = 128;             // the frame, square
constexpr int kSpot = 64;              // the bright texel's column and row
constexpr float kSpotRadiance = 11.0f; // within RGBM's range (16)
constexpr float kThreshold = 1.0f;
constexpr int kGlareScale = 8; // the glare image is this many times smaller

// Energy of an image (sum over texels of the channel mean) in frame pixels: a texel of an
// image `scale` times smaller covers scale^2 of them.
double energy(const ImageF& image, int scale)
{
    double sum = 0.0;
    for (int y = 0; y < image.height; ++y)
        for (int x = 0; x < image.width; ++x)
            sum += (image.at(x, y)[0] + image.at(x, y)[1] + image.at(x, y)[2]) / 3.0;
    return sum * scale * scale;
}

// The same for the texels whose centres lie within `radius` frame pixels of the spot's centre.
double energyWithin(const ImageF& image, int scale, double radius)
{
    double sum = 0.0;
    for (int y = 0; y < image.height; ++y)
        for (int x = 0; x < image.width; ++x) {
            const double dx = (x + 0.5) * scale - (kSpot + 0.5), dy = (y + 0.5) * scale - (kSpot + 0.5);
            if (dx * dx + dy * dy <= radius * radius)
                sum += (image.at(x, y)[0] + image.at(x, y)[1] + image.at(x, y)[2]) / 3.0;
        }
    return sum * scale * scale;
}

// A camera image holding every code value in each channel, the channels out of step.
Image8 codeRamp(int width, int height)
{
    Image8 ramp(width, height, 3);
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x)
            for (int c = 0; c < 3; ++c)
                ramp.at(x, y)[c] = uint8_t((x * 7 + y * 13 + c * 85) % 256);
    return ramp;
}

// Emissive cards (`halfSize` metres square, facing the camera, emitting `emission`) at
// `positions` in the camera frame, under a uniform sky over `camera`, through a renderer made
// with `options`; empty where no GLES 3 renderer can be made.
Image8 renderEmissiveCards(const RenderOptions& options, const Image8& camera, const CameraIntrinsics& k,
                           float emission, float halfSize, std::initializer_list<glm::vec3> positions)
{
    auto made = test::tryCreateRenderer(camera.width, camera.height, options);
    Image8 out;
    if (!made.renderer)
        return out;
    made.renderer->setEnvironment(test::uniformEnvironment(0.2f), 1.0f);
    const GltfModel card = test::cameraFacingRectangle(-halfSize, -halfSize, halfSize, halfSize,
                                                       test::emissiveMaterial(glm::vec3(emission)));
    const int model = made.renderer->addModel(card);
    std::vector<DrawItem> items;
    for (const glm::vec3& p : positions)
        items.push_back({model, test::translation(p.x, p.y, p.z)});
    made.renderer->render(camera, k, items);
    made.renderer->readback(out);
    return out;
}

// The images' formats: all RGBA16F; the radiance RGBA16F and the pyramid RGBM (a software
// rasteriser's choice); all RGBM (no float format renders).
enum class Formats { Float, Packed, Rgbm };

class LensFixture : public ::testing::Test {
protected:
    void SetUp() override
    {
        try {
            context_.emplace(EglDisplay::surfaceless());
        } catch (const RuntimeError& e) {
            GTEST_SKIP() << e.what();
        }
    }

    // The effects over a black frame whose only virtual light is a texel of `radiance` at
    // each of `spots` (column, row), with the images in `formats`.
    std::unique_ptr<LensEffects> applyToSpots(const LensOptions& options, const std::vector<glm::ivec2>& spots,
                                              float radiance, Formats formats)
    {
        target_.emplace(kSize, kSize, 1);
        LensOptions formatted = options;
        formatted.images = formats == Formats::Float ? LensImageFormat::Float : LensImageFormat::Rgbm;
        auto lens = std::make_unique<LensEffects>(*target_, formatted, formats == Formats::Rgbm);
        target_->bindForDrawing();
        glClearColor(0, 0, 0, 1);
        glClear(GL_COLOR_BUFFER_BIT);
        lens->beginVirtual();
        lens->endVirtual();
        glBindTexture(GL_TEXTURE_2D, lens->radianceTexture());
        // As mesh.frag writes it: the light above the threshold.
        radiance = std::max(radiance - options.threshold, 0.0f);
        if (lens->radianceRgbm()) {
            // rgbm.glsl's encoding.
            const float m = std::max(std::ceil(radiance / 16.0f * 255.0f), 1.0f) / 255.0f;
            const auto code = uint8_t(std::lround(std::min(1.0f, radiance / (m * 16.0f)) * 255.0f));
            const uint8_t texel[4] = {code, code, code, uint8_t(std::lround(m * 255.0f))};
            for (const glm::ivec2 spot : spots)
                glTexSubImage2D(GL_TEXTURE_2D, 0, spot.x, spot.y, 1, 1, GL_RGBA, GL_UNSIGNED_BYTE, texel);
        } else {
            const float texel[4] = {radiance, radiance, radiance, 1.0f};
            const GLenum format = lens->radianceFormat() == GL_R11F_G11F_B10F ? GL_RGB : GL_RGBA;
            for (const glm::ivec2 spot : spots)
                glTexSubImage2D(GL_TEXTURE_2D, 0, spot.x, spot.y, 1, 1, format, GL_FLOAT, texel);
        }
        lens->apply(*target_, PixelRect{0, 0, kSize, kSize});
        EXPECT_EQ(glGetError(), GLenum(GL_NO_ERROR));
        return lens;
    }

    // The frame after the effects, RGB.
    Image8 frame() const
    {
        Image8 rgba(kSize, kSize, 4);
        glBindFramebuffer(GL_READ_FRAMEBUFFER, target_->readFramebuffer());
        glReadPixels(0, 0, kSize, kSize, GL_RGBA, GL_UNSIGNED_BYTE, rgba.data.data());
        return rgba;
    }

    std::optional<EglContext> context_;
    std::optional<RenderTarget> target_;
};

// Each property in every format, drawn by GL over the whole frame and culled (the pyramid
// and the glare on the CPU, lens_cpu_passes.h).
class Lens : public LensFixture, public ::testing::WithParamInterface<std::tuple<Formats, LensCulling>> {
protected:
    std::unique_ptr<LensEffects> applyToSpot(const LensOptions& options, float radiance)
    {
        LensOptions culled = options;
        culled.culling = std::get<1>(GetParam());
        auto lens = applyToSpots(culled, {{kSpot, kSpot}}, radiance, std::get<0>(GetParam()));
        EXPECT_EQ(lens->culled(), culled.culling == LensCulling::Culled);
        return lens;
    }
};

LensOptions bloomOnly()
{
    LensOptions options;
    options.enabled = true;
    options.threshold = kThreshold;
    options.bloom = true;
    options.bloomIntensity = 1.0f;
    options.bloomRadius = 16.0f;
    options.glare = false;
    return options;
}

// The bloom of one bright texel carries its light above the threshold, 10, within 3 %, and
// spreads it: at most 60 % stays within 4 pixels, at least 90 % lies within the radius (16
// pixels) and at least 99 % within twice the radius.
TEST_P(Lens, BloomConservesTheBrightEnergyAndSpreadsItOverTheRadius)
{
    const auto lens = applyToSpot(bloomOnly(), kSpotRadiance);
    const double bright = kSpotRadiance - kThreshold;
    EXPECT_NEAR(energy(lens->readBright(), 2), bright, 0.01 * bright);
    const ImageF bloom = lens->readBloom();
    const double total = energy(bloom, 2);
    EXPECT_NEAR(total, bright, 0.03 * bright);
    const double near = energyWithin(bloom, 2, 4.0), inside = energyWithin(bloom, 2, 16.0),
                 wide = energyWithin(bloom, 2, 32.0);
    RecordProperty("share_within_4px", std::to_string(near / total));
    RecordProperty("share_within_16px", std::to_string(inside / total));
    EXPECT_LE(near, 0.6 * total);
    EXPECT_GE(inside, 0.9 * total);
    EXPECT_GE(wide, 0.99 * total);
    // In the frame: the spot's neighbourhood brightens, a corner stays black.
    const Image8 out = frame();
    EXPECT_GT(out.at(kSpot + 3, kSpot)[0], 0);
    EXPECT_EQ(out.at(2, 2)[0], 0);
}

// The glare's energy along a ray through the spot (the glare's texels from 8 to 32 pixels
// away) against the same strip turned half-way between two rays.
double stripEnergy(const ImageF& glare, double angleDegrees)
{
    const double a = angleDegrees * std::numbers::pi / 180.0;
    double sum = 0.0;
    for (double t = 8.0; t <= 32.0; t += 4.0) {
        const int x = int(std::floor((kSpot + 0.5 + t * std::cos(a)) / kGlareScale));
        const int y = int(std::floor((kSpot + 0.5 + t * std::sin(a)) / kGlareScale));
        if (x >= 0 && y >= 0 && x < glare.width && y < glare.height)
            sum += glare.at(x, y)[0];
    }
    return sum;
}

// Three streaks from 30 degrees (towards +x and +y, image right and down): light along 30,
// 150 and 270 degrees, ten times more than along the directions half-way between them, and
// opposite each ray (210, 330, 90) as little; the streaks carry the bright light's energy
// (at the eighth of the size the glare reads) within 3 %.
TEST_P(Lens, GlareStreaksRunAlongTheConfiguredRays)
{
    LensOptions options = bloomOnly();
    options.bloom = false;
    options.glare = true;
    options.glareStreaks = 3;
    options.glareAngle = 30.0f;
    options.glareLength = 48.0f;
    options.glareIntensity = 1.0f;
    const auto lens = applyToSpot(options, kSpotRadiance);
    const ImageF glare = lens->readGlare();
    const double bright = kSpotRadiance - kThreshold;
    EXPECT_NEAR(energy(glare, kGlareScale), bright, 0.03 * bright);
    for (const double ray : {30.0, 150.0, 270.0}) {
        SCOPED_TRACE(ray);
        const double along = stripEnergy(glare, ray);
        EXPECT_GT(along, 0.0);
        EXPECT_GT(along, 10.0 * stripEnergy(glare, ray + 60.0));  // between two rays
        EXPECT_GT(along, 10.0 * stripEnergy(glare, ray + 180.0)); // opposite: not a ray
    }
}

// Culled, the pyramid and the glare are computed on the CPU in float within reach of the
// bright texels: with two spots (one by a corner, where the reach leaves the frame) under
// bloom and glare, the bloom and the glare equal the whole-frame GL effects with float images
// texel by texel within 0.1 % of the brightest (RGBA16F's half precision; 1.5 % where the
// bright image is RGBM, 8 bits per step), and the frame within a code value.
class LensCulledEqualsWhole : public LensFixture, public ::testing::WithParamInterface<Formats> {};

TEST_P(LensCulledEqualsWhole, CulledEffectsEqualTheWholeFrames)
{
    LensOptions options = bloomOnly();
    options.glare = true;
    options.glareLength = 24.0f;
    options.glareAngle = 20.0f;
    // The largest intensities: the faint ends of the bloom and the streaks reach the frame's codes.
    options.bloomIntensity = 16.0f;
    options.glareIntensity = 16.0f;
    const std::vector<glm::ivec2> spots{{20, 24}, {kSize - 3, kSize - 2}};
    options.culling = LensCulling::Whole;
    const auto whole = applyToSpots(options, spots, kSpotRadiance, Formats::Float);
    const Image8 wholeFrame = frame();
    const ImageF wholeBloom = whole->readBloom(), wholeGlare = whole->readGlare();
    options.culling = LensCulling::Culled;
    const auto culled = applyToSpots(options, spots, kSpotRadiance, GetParam());
    ASSERT_TRUE(culled->culled());
    const Image8 culledFrame = frame();
    ASSERT_EQ(culledFrame.data.size(), wholeFrame.data.size());
    int worstCode = 0, changed = 0;
    for (size_t i = 0; i < wholeFrame.data.size(); ++i) {
        worstCode = std::max(worstCode, std::abs(int(culledFrame.data[i]) - int(wholeFrame.data[i])));
        changed += wholeFrame.data[i] != 0 && i % 4 != 3;
    }
    EXPECT_GT(changed, 100); // the effects reach the frame's codes
    EXPECT_LE(worstCode, 1);
    const float tolerance = GetParam() == Formats::Float ? 1e-3f : 1.5e-2f;
    const auto expectSame = [tolerance](const ImageF& a, const ImageF& b) {
        ASSERT_EQ(a.data.size(), b.data.size());
        float peak = 0.0f, worst = 0.0f;
        for (size_t i = 0; i < a.data.size(); ++i) {
            peak = std::max(peak, b.data[i]);
            worst = std::max(worst, std::abs(a.data[i] - b.data[i]));
        }
        EXPECT_GT(peak, 0.0f);
        EXPECT_LE(worst, tolerance * peak);
    };
    SCOPED_TRACE("bloom");
    expectSame(culled->readBloom(), wholeBloom);
    SCOPED_TRACE("glare");
    expectSame(culled->readGlare(), wholeGlare);
}

std::string formatName(Formats formats)
{
    return formats == Formats::Float ? "Float" : formats == Formats::Packed ? "Packed" : "Rgbm";
}

INSTANTIATE_TEST_SUITE_P(Formats, Lens,
                         ::testing::Combine(::testing::Values(Formats::Float, Formats::Packed, Formats::Rgbm),
                                            ::testing::Values(LensCulling::Whole, LensCulling::Culled)),
                         [](const ::testing::TestParamInfo<std::tuple<Formats, LensCulling>>& param) {
                             return formatName(std::get<0>(param.param)) +
                                    (std::get<1>(param.param) == LensCulling::Culled ? "Culled" : "Whole");
                         });
INSTANTIATE_TEST_SUITE_P(Formats, LensCulledEqualsWhole,
                         ::testing::Values(Formats::Float, Formats::Packed, Formats::Rgbm),
                         [](const ::testing::TestParamInfo<Formats>& param) { return formatName(param.param); });

// Through the whole renderer: every effect on (the threshold at 0), no virtual object, the
// camera image comes out as it went in (+-1), single- and multisampled, both formats.
TEST(LensRenderer, PassthroughWithEveryEffectOnEqualsTheInput)
{
    for (const bool rgbm : {false, true})
        for (const int samples : {1, 4}) {
            SCOPED_TRACE(std::string(rgbm ? "rgbm" : "float") + ", samples " + std::to_string(samples));
            RenderOptions options;
            options.samples = samples;
            options.environmentMaps.ibl.forceRgbm = rgbm;
            options.lens.enabled = true;
            options.lens.images = rgbm ? LensImageFormat::Rgbm : LensImageFormat::Float;
            options.lens.threshold = 0.0f;
            options.lens.glare = true;
            LUMAR_RENDERER_OR_SKIP(renderer, 96, 64, options);
            renderer.setEnvironment(test::uniformEnvironment(1.0f), 1.0f);
            const Image8 input = codeRamp(96, 64);
            renderer.render(input, test::makeIntrinsics(96, 64, 80, 80, 48, 32), {});
            Image8 out;
            renderer.readback(out);
            int worst = 0;
            for (int y = 0; y < 64; ++y)
                for (int x = 0; x < 96; ++x)
                    for (int c = 0; c < 3; ++c)
                        worst = std::max(worst, std::abs(int(out.at(x, y)[c]) - int(input.at(x, y)[c])));
            EXPECT_LE(worst, 1);
        }
}

// An emissive card brighter than the threshold over a grey camera image (single- and
// multisampled): with the effects on,
// the pixels around the card brighten and none darkens; far from it (beyond the bloom's radius
// and the streaks' length) the frame equals the one without effects. A card below the
// threshold gives the frame without effects exactly.
TEST(LensRenderer, AnEmissiveCardBloomsOnlyAboveTheThreshold)
{
    constexpr int kW = 160, kH = 120;
    const CameraIntrinsics k = test::makeIntrinsics(kW, kH, 100, 100, 80, 60);
    const Image8 grey = test::solidImage(kW, kH, 60, 60, 60);
    const auto renderCard = [&](bool lensOn, float emission, int samples) {
        RenderOptions options;
        options.samples = samples;
        options.lens.enabled = lensOn;
        options.lens.glare = true;
        options.lens.bloomRadius = 16.0f;
        options.lens.glareLength = 24.0f;
        return renderEmissiveCards(options, grey, k, emission, 0.05f, {{0, 0, 1}});
    };
    for (const int samples : {1, 4}) {
        SCOPED_TRACE("samples " + std::to_string(samples));
        const Image8 off = renderCard(false, 8.0f, samples);
        if (off.width == 0)
            GTEST_SKIP() << "no GLES 3 renderer";
        const Image8 on = renderCard(true, 8.0f, samples);
        int brighter = 0;
        for (int y = 0; y < kH; ++y)
            for (int x = 0; x < kW; ++x)
                for (int c = 0; c < 3; ++c) {
                    const int d = int(on.at(x, y)[c]) - int(off.at(x, y)[c]);
                    ASSERT_GE(d, -1) << x << "," << y;
                    brighter += d > 1;
                    // The card spans 70..90 x 50..70; bloom and glare reach 16 + 24 pixels past it.
                    if (x < 70 - 48 || x > 90 + 48 || y < 50 - 48 || y > 70 + 48) {
                        ASSERT_EQ(d, 0) << x << "," << y;
                    }
                }
        EXPECT_GT(brighter, 3 * 400);                       // more than the card's own area, three channels
        EXPECT_GT(on.at(80, 75)[0], off.at(80, 75)[0] + 5); // 5 pixels below the card
        const Image8 dimOff = renderCard(false, 0.5f, samples), dimOn = renderCard(true, 0.5f, samples);
        EXPECT_EQ(dimOn.data, dimOff.data);
    }
}

// The bloom's faint tail reaches far past the card: every pixel it touches is taken back to
// linear light, added to and encoded again, so that round trip must keep every code value.
// Over a camera image holding every code (dark ones too, where an sRGB fit is least exact: a
// cubic fit turned codes 1 to 53 up to 5 codes darker, fig. 6's darker pixels away from the
// lamps) no pixel comes out darker with the effects on than off, both image formats.
TEST(LensRenderer, NoCameraCodeDarkensUnderTheBloomsTail)
{
    constexpr int kW = 160, kH = 120;
    const CameraIntrinsics k = test::makeIntrinsics(kW, kH, 100, 100, 80, 60);
    const Image8 ramp = codeRamp(kW, kH);
    const auto renderCard = [&](bool lensOn, bool rgbm) {
        RenderOptions options;
        options.lens.enabled = lensOn;
        options.lens.images = rgbm ? LensImageFormat::Rgbm : LensImageFormat::Float;
        options.lens.glare = true;
        options.lens.bloomRadius = 16.0f;
        options.lens.glareLength = 24.0f;
        return renderEmissiveCards(options, ramp, k, 8.0f, 0.05f, {{0, 0, 1}});
    };
    for (const bool rgbm : {false, true}) {
        SCOPED_TRACE(rgbm ? "rgbm" : "float");
        const Image8 off = renderCard(false, rgbm);
        if (off.width == 0)
            GTEST_SKIP() << "no GLES 3 renderer";
        const Image8 on = renderCard(true, rgbm);
        int darker = 0, worst = 0;
        for (int y = 0; y < kH; ++y)
            for (int x = 0; x < kW; ++x)
                for (int c = 0; c < 3; ++c) {
                    const int d = int(on.at(x, y)[c]) - int(off.at(x, y)[c]);
                    darker += d < -1;
                    worst = std::min(worst, d);
                }
        EXPECT_EQ(darker, 0) << "the most: " << worst << " codes";
    }
}

// Through the whole renderer: three emissive cards (one half out of the frame) over the code
// ramp, bloom and glare on, single- and multisampled: the culled effects' frame is the
// whole-frame effects' frame within a code value (at most 1 % of the codes differ), and
// differs from the frame without effects.
TEST(LensRenderer, CulledEffectsGiveTheWholeFramesImage)
{
    constexpr int kW = 192, kH = 128;
    const CameraIntrinsics k = test::makeIntrinsics(kW, kH, 100, 100, 96, 64);
    const Image8 ramp = codeRamp(kW, kH);
    const auto render = [&](bool lensOn, LensCulling culling, int samples) {
        RenderOptions options;
        options.samples = samples;
        options.lens.enabled = lensOn;
        options.lens.culling = culling;
        // Float images: the culled effects are float maths on the CPU, the whole-frame GL
        // pyramid the same in RGBA16F (in RGBM it would sample the glare texel by texel).
        options.lens.images = LensImageFormat::Float;
        options.lens.glare = true;
        options.lens.glareAngle = 15.0f;
        options.lens.bloomRadius = 16.0f;
        options.lens.glareLength = 24.0f;
        return renderEmissiveCards(options, ramp, k, 8.0f, 0.02f,
                                   {{-0.5f, -0.3f, 1}, {0.3f, 0.2f, 1}, {0.97f, -0.1f, 1}});
    };
    for (const int samples : {1, 4}) {
        SCOPED_TRACE("samples " + std::to_string(samples));
        const Image8 off = render(false, LensCulling::Whole, samples);
        if (off.width == 0)
            GTEST_SKIP() << "no GLES 3 renderer";
        const Image8 whole = render(true, LensCulling::Whole, samples);
        const Image8 culled = render(true, LensCulling::Culled, samples);
        EXPECT_NE(whole.data, off.data);
        ASSERT_EQ(culled.data.size(), whole.data.size());
        int worst = 0, differing = 0;
        for (size_t i = 0; i < whole.data.size(); ++i) {
            const int d = std::abs(int(culled.data[i]) - int(whole.data[i]));
            worst = std::max(worst, d);
            differing += d > 0;
        }
        EXPECT_LE(worst, 1);
        EXPECT_LE(differing, int(whole.data.size() / 100));
    }
}

} // namespace
} // namespace lumar
