// Glass (KHR_materials_transmission, _ior, _volume; DESIGN.md §6.5) as the frame shows it: a
// glass sphere 1 m in front of the camera before a far, textured wall (an unlit quad 20 m
// away whose brightness rises from left to right), lit by a uniform environment. The sphere
// sees the wall in its own environment map, so through it the wall must show: refracted
// (IOR 1.5 bends the view and turns the ramp round, as a ball lens shows the world upside
// down), not lost (its brightness kept), straight through for IOR 1 (nearly the wall itself),
// and at grazing angles the Fresnel-weighted reflection must take over from the light through.
// Every check reads pixels of the rendered frame, found by intersecting each pixel's ray
// with the analytic sphere.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <optional>
#include <string_view>
#include <vector>

#include <glm/gtc/matrix_transform.hpp>
#include <gtest/gtest.h>

#include "../unit/render/render_test_support.h"
#include "gl_test_support.h"
#include "gles_renderer/assets/builtin_shapes.h"
#include "gles_renderer/assets/lafortune_material.h"

namespace lumar {
namespace {

constexpr int kWidth = 160, kHeight = 120;
constexpr double kFocal = 150.0;
constexpr double kSphereDepth = 1.0, kSphereRadius = 0.2; // camera frame, metres
constexpr double kWallDepth = 20.0;
// Wide enough for the bent views through the sphere (up to 48 degrees off the axis).
constexpr float kWallHalfWidth = 40.0f;
constexpr float kEnvironment = 0.3f; // uniform sky radiance

// Linear radiance of the wall's ramp texel i of 256: 0.05 at the left, 0.6 at the right.
double rampRadiance(int i)
{
    return 0.05 + 0.55 * i / 255.0;
}

GltfModel wall(bool ramp, float halfWidth = kWallHalfWidth)
{
    GltfMaterial material;
    material.unlit = true;
    material.baseColorFactor = ramp ? glm::vec4(1.0f) : glm::vec4(glm::vec3(kEnvironment), 1.0f);
    GltfModel model = test::cameraFacingRectangle(-halfWidth, -30.0f, halfWidth, 30.0f, material);
    if (ramp) {
        GltfTexture texture;
        texture.srgb = true;
        texture.image = Image8(256, 1, 4);
        for (int i = 0; i < 256; ++i) {
            const auto code = uint8_t(std::lround(255.0 * test::srgbEncode(rampRadiance(i))));
            uint8_t* texel = texture.image.at(i, 0);
            texel[0] = texel[1] = texel[2] = code;
            texel[3] = 255;
        }
        model.textures.push_back(std::move(texture));
        model.materials[0].baseColorTexture = 0;
    }
    return model;
}

// Metallic-roughness glass, solid (it bends the view), tinted as glTF tints it: by the base colour.
GltfMaterial glass(float ior, glm::vec3 tint = glm::vec3(1.0f))
{
    GltfMaterial m;
    m.baseColorFactor = glm::vec4(tint, 1.0f);
    m.metallicFactor = 0.0f;
    m.roughnessFactor = 0.0f;
    m.transmission.factor = 1.0f;
    m.transmission.ior = ior;
    m.transmission.thickness = 0.4f;
    m.transmission.tint = tint;
    return m;
}

// Glass that reflects nothing (Lafortune rho_s 0, no Fresnel factor): the light through alone.
GltfMaterial clearNonReflecting(float ior)
{
    GltfMaterial m = glass(ior);
    m.hasLafortune = true;
    m.lafortune.diffuse = glm::vec3(0.0f);
    m.lafortune.specular = glm::vec3(0.0f);
    m.lafortune.exponent = 4096.0f;
    m.lafortune.fresnelPhi = 0.0f;
    return m;
}

// A material preset as a sidecar's `preset = "..."` gives it: its Lafortune surface and the
// light it lets through.
GltfMaterial presetMaterial(std::string_view name)
{
    GltfMaterial m;
    m.hasLafortune = true;
    m.lafortune = *materialPreset(name);
    m.transmission = materialPresetTransmission(name);
    return m;
}

// The wall alone, or with `model` placed by `cameraFromModel` in front of it; empty without GLES 3.
std::optional<Image8> renderModel(const GltfModel& wallModel, const GltfModel* model, const glm::dmat4& cameraFromModel)
{
    test::RendererOrReason made = test::tryCreateRenderer(kWidth, kHeight);
    if (!made.renderer)
        return std::nullopt;
    SceneRenderer& renderer = *made.renderer;
    renderer.setEnvironment(test::uniformEnvironment(kEnvironment), 1.0f);
    std::vector<DrawItem> items;
    items.push_back({renderer.addModel(wallModel), test::translation(0, 0, kWallDepth), 1});
    if (model)
        items.push_back({renderer.addModel(*model), cameraFromModel, 0});
    const Image8 black = test::solidImage(kWidth, kHeight, 0, 0, 0);
    const CameraIntrinsics k = test::makeIntrinsics(kWidth, kHeight, kFocal, kFocal, kWidth / 2.0, kHeight / 2.0);
    renderer.render(black, k, items);
    Image8 frame;
    renderer.readback(frame);
    return frame;
}

// The wall alone, or with the sphere of `material` in front of it.
std::optional<Image8> render(bool ramp, const std::optional<GltfMaterial>& material)
{
    if (!material)
        return renderModel(wall(ramp), nullptr, glm::dmat4(1.0));
    GltfModel sphere = makeUvSphere(64, 32);
    sphere.materials[0] = *material;
    const glm::dmat4 cameraFromModel =
        glm::scale(test::translation(0, 0, kSphereDepth), glm::dvec3(2.0 * kSphereRadius));
    return renderModel(wall(ramp), &sphere, cameraFromModel);
}

#define RENDER_OR_SKIP(frame, ...)                                                                                     \
    const std::optional<Image8> frame##Optional = render(__VA_ARGS__);                                                 \
    if (!frame##Optional)                                                                                              \
        GTEST_SKIP() << "no GLES 3 renderer";                                                                          \
    const Image8& frame = *frame##Optional

// The cosine of the angle between pixel (u, v)'s ray and the sphere's normal where the ray
// enters it; nothing where the ray misses.
std::optional<double> incidence(int u, int v)
{
    const glm::dvec3 d =
        glm::normalize(glm::dvec3((u + 0.5 - kWidth / 2.0) / kFocal, (v + 0.5 - kHeight / 2.0) / kFocal, 1));
    const glm::dvec3 c(0, 0, kSphereDepth);
    const double b = glm::dot(d, c);
    const double disc = b * b - (glm::dot(c, c) - kSphereRadius * kSphereRadius);
    if (disc <= 0.0)
        return std::nullopt;
    const glm::dvec3 n = (d * (b - std::sqrt(disc)) - c) / kSphereRadius;
    return -glm::dot(d, n);
}

glm::dvec3 linearAt(const Image8& image, int u, int v)
{
    const uint8_t* p = image.data.data() + (size_t(v) * size_t(kWidth) + size_t(u)) * 3;
    return {test::srgbDecode(p[0] / 255.0), test::srgbDecode(p[1] / 255.0), test::srgbDecode(p[2] / 255.0)};
}

// The pixels whose ray enters the sphere with a cosine in [lo, hi].
std::vector<glm::ivec2> pixelsWithIncidence(double lo, double hi)
{
    std::vector<glm::ivec2> pixels;
    for (int v = 0; v < kHeight; ++v)
        for (int u = 0; u < kWidth; ++u)
            if (const std::optional<double> c = incidence(u, v); c && *c >= lo && *c <= hi)
                pixels.push_back({u, v});
    return pixels;
}

double meanGreen(const Image8& image, const std::vector<glm::ivec2>& pixels)
{
    double sum = 0.0;
    for (const glm::ivec2 p : pixels)
        sum += linearAt(image, p.x, p.y).g;
    return sum / double(pixels.size());
}

// Least-squares slope of linear brightness against u along the sphere's middle row, over its
// inner part (incidence cosine above 0.6, so the reflection stays small).
double middleRowSlope(const Image8& image)
{
    const int v = kHeight / 2;
    double n = 0, su = 0, sy = 0, suu = 0, suy = 0;
    for (int u = 0; u < kWidth; ++u) {
        const std::optional<double> c = incidence(u, v);
        if (!c || *c < 0.6)
            continue;
        const double y = linearAt(image, u, v).g;
        n += 1;
        su += u;
        sy += y;
        suu += double(u) * u;
        suy += u * y;
    }
    return (n * suy - su * sy) / (n * suu - su * su);
}

TEST(Glass, TheWallIsSeenRefractedThroughTheSphereAndNotLost)
{
    RENDER_OR_SKIP(wallAlone, true, std::nullopt);
    RENDER_OR_SKIP(throughGlass, true, glass(1.5f));
    const std::vector<glm::ivec2> inner = pixelsWithIncidence(0.3, 1.0);
    ASSERT_GT(inner.size(), 1000u);

    // The wall's ramp rises to the right; through solid glass of index 1.5 the view is bent
    // towards the axis and crosses it (each pixel left of the centre looks right of it), so
    // the ramp falls: displaced, and turned round.
    const double wallSlope = middleRowSlope(wallAlone);
    const double glassSlope = middleRowSlope(throughGlass);
    const double wallMean = meanGreen(wallAlone, inner);
    const double glassMean = meanGreen(throughGlass, inner);
    std::printf("middle-row slope: wall %.5f, through glass %.5f per pixel; mean: wall %.4f, through glass %.4f\n",
                wallSlope, glassSlope, wallMean, glassMean);
    EXPECT_GT(wallSlope, 0.0);
    EXPECT_LT(glassSlope, -0.5 * wallSlope) << "wall " << wallSlope << ", through glass " << glassSlope;

    // Not lost: the mean brightness behind the glass stays within 20% of the wall's there
    // (4% goes to the reflection, which shows the sky and the wall again).
    EXPECT_NEAR(glassMean / wallMean, 1.0, 0.2) << "wall " << wallMean << ", through glass " << glassMean;
}

// The presets as the milk truck's windows use them: the `glass` preset is solid (a ball of it
// turns the wall's ramp round, as the metallic-roughness glass above does), `thin_glass` a
// thin-walled pane: the view passes straight through, so the ramp keeps its direction and
// steepness behind it (only the environment map's 5% nearer viewpoint and the rim's
// reflection change it), and its brightness.
TEST(Glass, ThinGlassPresetDoesNotBendTheViewAndSolidGlassDoes)
{
    RENDER_OR_SKIP(wallAlone, true, std::nullopt);
    RENDER_OR_SKIP(solid, true, presetMaterial("glass"));
    RENDER_OR_SKIP(thin, true, presetMaterial("thin_glass"));
    const std::vector<glm::ivec2> inner = pixelsWithIncidence(0.3, 1.0);
    ASSERT_GT(inner.size(), 1000u);
    const double wallSlope = middleRowSlope(wallAlone);
    const double solidSlope = middleRowSlope(solid);
    const double thinSlope = middleRowSlope(thin);
    const double wallMean = meanGreen(wallAlone, inner);
    const double thinMean = meanGreen(thin, inner);
    std::printf("middle-row slope: wall %.5f, glass preset %.5f, thin_glass preset %.5f per pixel; "
                "mean: wall %.4f, thin_glass %.4f\n",
                wallSlope, solidSlope, thinSlope, wallMean, thinMean);
    EXPECT_GT(wallSlope, 0.0);
    EXPECT_LT(solidSlope, -0.5 * wallSlope) << "solid glass turns the ramp round";
    EXPECT_NEAR(thinSlope / wallSlope, 1.0, 0.2) << "a pane keeps the ramp's direction and steepness";
    EXPECT_NEAR(thinMean / wallMean, 1.0, 0.1) << "and its brightness, less the 4% reflected";
}

TEST(Glass, IndexOneWithoutReflectionLeavesTheWallNearlyUndistorted)
{
    RENDER_OR_SKIP(wallAlone, true, std::nullopt);
    RENDER_OR_SKIP(throughGlass, true, clearNonReflecting(1.0f));
    // Inside the sphere's silhouette (its outermost pixel ring left out: the polygon's edge).
    const std::vector<glm::ivec2> disc = pixelsWithIncidence(0.15, 1.0);
    ASSERT_GT(disc.size(), 1000u);
    double sumDifference = 0.0, maxDifference = 0.0;
    for (const glm::ivec2 p : disc) {
        const uint8_t* a = wallAlone.data.data() + (size_t(p.y) * size_t(kWidth) + size_t(p.x)) * 3;
        const uint8_t* b = throughGlass.data.data() + (size_t(p.y) * size_t(kWidth) + size_t(p.x)) * 3;
        const double difference = std::abs(double(a[1]) - double(b[1]));
        sumDifference += difference;
        maxDifference = std::max(maxDifference, difference);
    }
    const double ratio = middleRowSlope(throughGlass) / middleRowSlope(wallAlone);
    std::printf("index 1: mean |difference| %.2f, largest %.0f code values, slope ratio %.3f\n",
                sumDifference / double(disc.size()), maxDifference, ratio);
    // The maps see the wall from the sphere's centre, 1 m nearer than the camera: it looks 5%
    // larger there, a few code values over the sphere's width, plus the map's texels.
    EXPECT_LT(sumDifference / double(disc.size()), 3.0);
    EXPECT_LT(maxDifference, 10.0);
    EXPECT_NEAR(ratio, 1.0, 0.15) << "the ramp keeps its direction and steepness";
}

TEST(Glass, AtGrazingAnglesTheReflectionDominates)
{
    // A green glass pane (1 m x 0.6 m, 1.5 m away) before a grey wall under a grey sky of the
    // same radiance: the light through it is green alone, the reflection grey, so red / green
    // over the pane is the share the reflection takes. Facing the camera that is rho_s = 0.04;
    // turned 87 degrees away (the view grazes it at 85.5 to 88.5 degrees) the paper's Fresnel
    // factor f = (1 - cos)^5 (phi = 1/6) raises rho_s' = 0.04 + 0.96 f and the falloff to
    // about 0.75 each, which leaves the light through about 0.25: red / green 0.6 to 0.8.
    const GltfModel flatWall = wall(false);
    const GltfModel pane =
        test::cameraFacingRectangle(-0.5f, -0.3f, 0.5f, 0.3f, glass(1.5f, glm::vec3(0.0f, 1.0f, 0.0f)));
    const auto reflectedShare = [&](double degrees) -> std::optional<double> {
        const glm::dmat4 cameraFromModel =
            glm::rotate(test::translation(0, 0, 1.5), glm::radians(degrees), glm::dvec3(0, 1, 0));
        const std::optional<Image8> alone = renderModel(flatWall, nullptr, glm::dmat4(1.0));
        const std::optional<Image8> frame = renderModel(flatWall, &pane, cameraFromModel);
        if (!alone || !frame)
            return std::nullopt;
        double red = 0.0, green = 0.0;
        size_t covered = 0;
        for (int v = 0; v < kHeight; ++v)
            for (int u = 0; u < kWidth; ++u) {
                const size_t i = (size_t(v) * size_t(kWidth) + size_t(u)) * 3;
                if (int(alone->data[i]) - int(frame->data[i]) <= 8)
                    continue; // the wall: the pane takes red away
                const glm::dvec3 c = linearAt(*frame, u, v);
                red += c.r;
                green += c.g;
                ++covered;
            }
        EXPECT_GT(covered, 150u) << degrees << " degrees";
        return red / green;
    };
    const std::optional<double> facing = reflectedShare(0.0);
    if (!facing)
        GTEST_SKIP() << "no GLES 3 renderer";
    const std::optional<double> grazing = reflectedShare(87.0);
    ASSERT_TRUE(grazing);
    std::printf("reflected share (red / green): facing %.3f, grazing %.3f\n", *facing, *grazing);
    EXPECT_LT(*facing, 0.1) << "facing the camera the glass lets nearly everything through";
    EXPECT_GT(*grazing, 0.5) << "at grazing angles the reflection dominates";
}

// The shared ToyCar (KHR_materials_transmission on its "Glass", thin-walled, base colour
// (0.3, 0.8, 0.3)): its glass canopy alone, seen from above before the ramp wall, shows the
// wall through it, tinted: where the glass covers the wall the red falls to about 0.3 of the
// wall's and the green follows the wall's from pixel to pixel.
TEST(Glass, ToyCarsGlassIsSeeThrough)
{
    const std::filesystem::path file = test::sharedDataPath("models/ToyCar.glb");
    if (!std::filesystem::exists(file))
        GTEST_SKIP() << file << " is absent (../shared/data exists on development machines only)";
    GltfModel car = loadGltfModel(file);
    ASSERT_EQ(car.materials.size(), 3u);
    const GltfTransmission& glass = car.materials[2].transmission;
    EXPECT_EQ(glass.factor, 1.0f);
    EXPECT_EQ(glass.thickness, 0.0f) << "no KHR_materials_volume: thin-walled";
    EXPECT_NEAR(glass.tint.g, 0.8f, 1e-6f);
    // The glass primitives alone, their bounds.
    std::erase_if(car.primitives, [](const GltfPrimitive& p) { return p.material != 2; });
    ASSERT_FALSE(car.primitives.empty());
    glm::vec3 lo(std::numeric_limits<float>::max()), hi(-std::numeric_limits<float>::max());
    for (const GltfPrimitive& p : car.primitives)
        for (const glm::vec3& position : p.positions) {
            const glm::vec3 q(p.modelFromMesh * glm::vec4(position, 1.0f));
            lo = glm::min(lo, q);
            hi = glm::max(hi, q);
        }
    car.boundsMin = lo;
    car.boundsMax = hi;
    // From above: the model's +Y towards the camera, its longest side 0.4 m at 1 m.
    const double scale = 0.4 / double(std::max({hi.x - lo.x, hi.y - lo.y, hi.z - lo.z}));
    const glm::dvec3 centre = 0.5 * (glm::dvec3(lo) + glm::dvec3(hi));
    const glm::dmat4 cameraFromModel = glm::translate(
        glm::scale(glm::rotate(test::translation(0, 0, kSphereDepth), glm::radians(-90.0), glm::dvec3(1, 0, 0)),
                   glm::dvec3(scale)),
        -centre);
    const GltfModel steepWall = wall(true, 12.0f);
    const std::optional<Image8> alone = renderModel(steepWall, nullptr, glm::dmat4(1.0));
    if (!alone)
        GTEST_SKIP() << "no GLES 3 renderer";
    const std::optional<Image8> through = renderModel(steepWall, &car, cameraFromModel);
    ASSERT_TRUE(through);

    std::vector<glm::dvec2> greens; // (wall, through the glass), linear
    for (int v = 0; v < kHeight; ++v)
        for (int u = 0; u < kWidth; ++u) {
            const glm::dvec3 a = linearAt(*alone, u, v), b = linearAt(*through, u, v);
            if (b.r < 0.6 * a.r)
                greens.push_back({a.g, b.g});
        }
    ASSERT_GT(greens.size(), 300u) << "the glass covers part of the wall";
    double n = 0, sx = 0, sy = 0, sxx = 0, syy = 0, sxy = 0;
    for (const glm::dvec2 g : greens) {
        n += 1;
        sx += g.x;
        sy += g.y;
        sxx += g.x * g.x;
        syy += g.y * g.y;
        sxy += g.x * g.y;
    }
    const double covariance = n * sxy - sx * sy;
    const double correlation = covariance / std::sqrt((n * sxx - sx * sx) * (n * syy - sy * sy));
    const double slope = covariance / (n * sxx - sx * sx);
    std::printf("ToyCar glass: %zu pixels, green through against the wall's: correlation %.3f, slope %.3f\n",
                greens.size(), correlation, slope);
    EXPECT_GT(correlation, 0.8) << "the wall's ramp shows through the glass";
    EXPECT_NEAR(slope, 0.8 * 0.96, 0.2) << "green passes at the tint's 0.8 less the 4% reflected";
}

} // namespace
} // namespace lumar
