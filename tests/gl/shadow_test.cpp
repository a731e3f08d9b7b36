// Shadows and contact darkening (DESIGN.md §6.5): a configured directional light's shadow map,
// virtual objects shadowing each other (mesh.frag), the differential darkening of the camera
// image on phantoms and receiver-only ground (phantom_receiver.frag), and the analytic contact
// occlusion. The scene is seen from 1 m straight above the world origin (world z up), under a
// uniform environment, over a uniform grey camera image.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <numbers>
#include <optional>
#include <vector>

#include <glm/gtc/matrix_transform.hpp>
#include <gtest/gtest.h>

#include "gl_test_support.h"
#include "gles_renderer/assets/builtin_shapes.h"
#include "gles_renderer/assets/gltf_model.h"
#include "gles_renderer/assets/lafortune_material.h"
#include "unit/render/animated_gltf.h"

namespace lumar {
namespace {

constexpr int kWidth = 200, kHeight = 150;
constexpr double kFocal = 250.0, kCx = 99.5, kCy = 74.5;
constexpr uint8_t kGrey = 128;
constexpr double kPi = std::numbers::pi;

const CameraIntrinsics& intrinsics()
{
    static const CameraIntrinsics k = test::makeIntrinsics(kWidth, kHeight, kFocal, kFocal, kCx, kCy);
    return k;
}

// The camera 1 m above the origin looking down: image x along world x, image y along -y.
glm::dmat4 cameraFromWorld()
{
    return test::cameraLookingDownFromOneMetre();
}

// World (z up, as a marker frame) to the environment frame (+Y up): (x, y, z) -> (x, z, -y).
glm::dmat3 environmentFromWorld()
{
    return glm::dmat3(glm::dvec3(1, 0, 0), glm::dvec3(0, 0, -1), glm::dvec3(0, 1, 0));
}

// Where world point p appears (pixel centre coordinates).
glm::dvec2 pixelOf(const glm::dvec3& p)
{
    const glm::dvec3 c(cameraFromWorld() * glm::dvec4(p, 1.0));
    return {kCx + kFocal * c.x / c.z, kCy + kFocal * c.y / c.z};
}

glm::dmat4 placed(const glm::dvec3& centre, const glm::dvec3& size)
{
    glm::dmat4 m(1.0);
    m[0][0] = size.x;
    m[1][1] = size.y;
    m[2][2] = size.z;
    m[3] = glm::dvec4(centre, 1.0);
    return cameraFromWorld() * m;
}

// Towards the light: elevation above the ground, azimuth from world +x towards +y.
glm::dvec3 worldDirection(double elevationDeg, double azimuthDeg)
{
    const double e = elevationDeg * kPi / 180.0, a = azimuthDeg * kPi / 180.0;
    return {std::cos(e) * std::cos(a), std::cos(e) * std::sin(a), std::sin(e)};
}

DirectionalLight light(const glm::dvec3& worldTowardsLight, float intensity)
{
    DirectionalLight l;
    l.direction = environmentFromWorld() * worldTowardsLight;
    l.color = glm::vec3(1.0f);
    l.intensity = intensity;
    return l;
}

RenderOptions shadowsOn()
{
    RenderOptions options;
    options.shadows.enabled = true;
    options.shadows.mapSize = 1024;
    options.shadows.softness = 1.5f;
    return options;
}

// A renderer under a uniform sky of radiance `radiance`, its environment turned with the world.
void prepare(SceneRenderer& renderer, float radiance)
{
    renderer.setEnvironment(test::uniformEnvironment(radiance), 1.0f);
    renderer.setEnvironmentRotation(environmentFromWorld() * glm::dmat3(glm::inverse(cameraFromWorld())));
}

Image8 renderOverGrey(SceneRenderer& renderer, std::span<const DrawItem> items)
{
    renderer.render(test::solidImage(kWidth, kHeight, kGrey, kGrey, kGrey), intrinsics(), items);
    Image8 out;
    renderer.readback(out);
    return out;
}

int code(const Image8& image, const glm::dvec2& pixel)
{
    return image.at(int(std::lround(pixel.x)), int(std::lround(pixel.y)))[1];
}

// A receiver-only ground: a quad of side 1 in the plane z = 0, facing +z (as the app's).
GltfModel groundQuad()
{
    return test::makeQuad({glm::vec3(-0.5f, -0.5f, 0.0f), glm::vec3(0.5f, -0.5f, 0.0f), glm::vec3(0.5f, 0.5f, 0.0f),
                           glm::vec3(-0.5f, 0.5f, 0.0f)},
                          GltfMaterial{});
}

// The ground: a phantom slab whose top is the plane z = 0.
DrawItem groundPhantom(ModelId cube)
{
    return {cube, placed({0.0, 0.0, -0.01}, {1.2, 1.2, 0.02}), -1, true};
}

// The floating box's scene (AFloatingBoxShadowsTheGroundPhantomByTheLightsShare and the tests
// after it): a box of side 0.1 m centred 0.3 m above the ground phantom, a light of intensity
// 2 at 60 degrees from world +x, a uniform sky L = 1.
constexpr double kFloatingBoxHeight = 0.3;

glm::dvec3 floatingBoxCentre()
{
    return {0.0, 0.0, kFloatingBoxHeight};
}

glm::dvec3 floatingBoxTowardsLight()
{
    return worldDirection(60.0, 0.0);
}

// The umbra's middle: the box centre's shadow on the ground.
glm::dvec3 floatingBoxShadowCentre()
{
    const glm::dvec3 towardsLight = floatingBoxTowardsLight();
    return floatingBoxCentre() - towardsLight * (kFloatingBoxHeight / towardsLight.z);
}

// The sky and the light on `renderer`; returns the cube the box and the ground are made of.
ModelId prepareFloatingBox(SceneRenderer& renderer)
{
    prepare(renderer, 1.0f);
    renderer.setLight(light(floatingBoxTowardsLight(), 2.0f));
    return renderer.addModel(makeCube());
}

// The code value of the grey camera image in the umbra of a light of intensity 2 at 60
// degrees' elevation under a uniform sky L = 1 (the floating box's; derived above
// AFloatingBoxShadowsTheGroundPhantomByTheLightsShare): 128 -> 89.
double umbraCode()
{
    return kGrey * std::pow(1.0 - 2.0 * std::sin(kPi / 3.0) / kPi, 1.0 / 2.2);
}

// The centroid of the pixels darker than the camera image by more than 10 code values.
glm::dvec2 darkCentroid(const Image8& image, int* count = nullptr)
{
    glm::dvec2 sum(0.0);
    int n = 0;
    for (int y = 0; y < image.height; ++y)
        for (int x = 0; x < image.width; ++x)
            if (image.at(x, y)[1] < kGrey - 10) {
                sum += glm::dvec2(x, y);
                ++n;
            }
    if (count)
        *count = n;
    return n > 0 ? sum / double(n) : glm::dvec2(-1.0);
}

// A box floating 0.3 m above the ground phantom, far enough (4.8 radii of its equal-volume
// sphere) that its contact darkening is exactly zero: the ground's darkening is its shadow
// alone. Uniform sky L = 1 (ground irradiance E_env = pi), light intensity 2 at 60 degrees:
// E_L = 2 sin 60 = 1.732, so the umbra multiplies the linear camera value by
// 1 - E_L / E_env = 0.449, written as the encoded factor 0.449^(1/2.2) = 0.695: 128 -> 89.
TEST(Shadows, AFloatingBoxShadowsTheGroundPhantomByTheLightsShare)
{
    LUMAR_RENDERER_OR_SKIP(renderer, kWidth, kHeight, shadowsOn());
    const ModelId cube = prepareFloatingBox(renderer);
    const DrawItem items[] = {groundPhantom(cube), {cube, placed(floatingBoxCentre(), glm::dvec3(0.1)), -1}};
    const Image8 out = renderOverGrey(renderer, items);

    const glm::dvec3 shadowCentre = floatingBoxShadowCentre();
    const double expected = umbraCode();
    for (const glm::dvec3& offset : {glm::dvec3(0.0), glm::dvec3(0.02, 0.0, 0.0), glm::dvec3(0.0, 0.02, 0.0)})
        EXPECT_NEAR(code(out, pixelOf(shadowCentre + offset)), expected, 3.0)
            << "ground at " << offset.x << "," << offset.y;
    // Pixels outside every shadow: the camera image within one code value (most exactly).
    int unchanged = 0, total = 0;
    for (int y = 0; y < kHeight; ++y)
        for (int x = 0; x < kWidth; ++x) {
            const bool farFromShadow = x > int(pixelOf({0.0, 0.0, 0.0}).x) + 45 || y < 20 || y > kHeight - 20;
            if (!farFromShadow)
                continue;
            for (int c = 0; c < 3; ++c) {
                ASSERT_NEAR(out.at(x, y)[c], kGrey, 1) << x << "," << y;
                unchanged += out.at(x, y)[c] == kGrey;
                ++total;
            }
        }
    EXPECT_EQ(unchanged, total);
}

// Translucent casters cast partial shadows (depth_only.frag's dither, averaged by the PCF): a
// floating panel (0.1 x 0.1 x 0.01 m, 0.3 m above the ground phantom, as the box above) casts
// the umbra of the light's share when opaque; blended with alpha 0.5 it stops half the light,
// so the darkening of the ground (1 - linear ratio) is half the opaque one's; of clear glass
// (the thin_glass preset: transmission 1, 4% reflected) it stops about 4% (one texel in 16 of
// the dither). Measured as the mean over the umbra's middle (15 x 15 pixels, 0.06 m square).
TEST(Shadows, TranslucentCastersCastPartialShadows)
{
    const glm::dvec3 towardsLight = worldDirection(60.0, 0.0);
    const glm::dvec3 panelCentre(0.0, 0.0, 0.3);
    const glm::dvec3 shadowCentre = panelCentre - towardsLight * (panelCentre.z / towardsLight.z);
    const auto darkening = [&](const GltfMaterial& material) -> std::optional<double> {
        test::RendererOrReason made = test::tryCreateRenderer(kWidth, kHeight, shadowsOn());
        if (!made.renderer)
            return std::nullopt;
        SceneRenderer& renderer = *made.renderer;
        prepare(renderer, 1.0f);
        renderer.setLight(light(towardsLight, 2.0f));
        GltfModel panel = makeCube();
        panel.materials[0] = material;
        const ModelId cube = renderer.addModel(makeCube());
        const ModelId panelId = renderer.addModel(panel);
        const DrawItem items[] = {groundPhantom(cube), {panelId, placed(panelCentre, {0.1, 0.1, 0.01}), -1}};
        const Image8 out = renderOverGrey(renderer, items);
        const glm::dvec2 centre = pixelOf(shadowCentre);
        const double grey = test::srgbDecode(kGrey / 255.0);
        double sum = 0.0;
        int n = 0;
        for (int dy = -7; dy <= 7; ++dy)
            for (int dx = -7; dx <= 7; ++dx) {
                const int value = out.at(int(std::lround(centre.x)) + dx, int(std::lround(centre.y)) + dy)[1];
                sum += 1.0 - test::srgbDecode(value / 255.0) / grey;
                ++n;
            }
        return sum / n;
    };
    const std::optional<double> opaque = darkening(GltfMaterial{});
    if (!opaque)
        GTEST_SKIP() << "no GLES 3 renderer";
    GltfMaterial blend;
    blend.alphaMode = GltfAlphaMode::Blend;
    blend.baseColorFactor.a = 0.5f;
    GltfMaterial glass;
    glass.hasLafortune = true;
    glass.lafortune = *materialPreset("thin_glass");
    glass.transmission = materialPresetTransmission("thin_glass");
    const double half = *darkening(blend);
    const double clear = *darkening(glass);
    std::printf("umbra darkening: opaque %.4f, alpha 0.5 %.4f (ratio %.3f), thin glass %.4f (ratio %.3f)\n", *opaque,
                half, half / *opaque, clear, clear / *opaque);
    // The opaque panel's umbra is the light's share, as before: 1 - E_L / E_env.
    EXPECT_NEAR(*opaque, 2.0 * std::sin(kPi / 3.0) / kPi, 0.03);
    EXPECT_NEAR(half / *opaque, 0.5, 0.1);
    EXPECT_GT(clear / *opaque, 0.0) << "glass reflects a little of the light";
    EXPECT_LT(clear / *opaque, 0.12);
}

// The darkening is shaded at a fraction of the frame's resolution (ShadowOptions::receiverScale)
// and filtered up: at full, half and quarter resolution the umbra keeps its value, the shadow its
// place and size, and the pixels outside it stay exactly the camera's. (200 x 150 is not a
// multiple of 4: quarter falls back to half, which must give half's image.)
TEST(Shadows, EveryReceiverResolutionGivesTheSameShadow)
{
    const double expected = umbraCode();
    const glm::dvec3 shadowCentre = floatingBoxShadowCentre();
    std::vector<Image8> images;
    for (int scale : {1, 2, 4}) {
        RenderOptions options = shadowsOn();
        options.shadows.receiverScale = scale;
        LUMAR_RENDERER_OR_SKIP(renderer, kWidth, kHeight, options);
        const ModelId cube = prepareFloatingBox(renderer);
        const DrawItem items[] = {groundPhantom(cube), {cube, placed(floatingBoxCentre(), glm::dvec3(0.1)), -1}};
        images.push_back(renderOverGrey(renderer, items));
        EXPECT_NEAR(code(images.back(), pixelOf(shadowCentre)), expected, 3.0) << "scale " << scale;
    }
    int fullCount = 0;
    const glm::dvec2 fullCentroid = darkCentroid(images[0], &fullCount);
    ASSERT_GT(fullCount, 200);
    int halfCount = 0;
    const glm::dvec2 halfCentroid = darkCentroid(images[1], &halfCount);
    EXPECT_NEAR(halfCentroid.x, fullCentroid.x, 1.0);
    EXPECT_NEAR(halfCentroid.y, fullCentroid.y, 1.0);
    EXPECT_NEAR(double(halfCount) / fullCount, 1.0, 0.1);
    int differing = 0;
    for (int y = 0; y < kHeight; ++y)
        for (int x = 0; x < kWidth; ++x) {
            ASSERT_EQ(images[2].at(x, y)[1], images[1].at(x, y)[1])
                << "quarter falls back to half at " << x << "," << y;
            if (images[0].at(x, y)[1] == kGrey) // outside the shadow at full resolution
                differing += std::abs(images[1].at(x, y)[1] - kGrey) > 1;
        }
    // Only the shadow's outline, where a half-resolution texel straddles it, may darken.
    EXPECT_LT(differing, 2 * kHeight) << "pixels outside the shadow darkened at half resolution";
}

// ShadowPass shades the darkening only in the tiles where a shadow's parallelogram or a
// contact's ellipse falls (tile_cover.h): the frame equals the one shaded over the whole
// buffer (+-1). Seen obliquely (so the receivers' faces project with perspective), a ground
// phantom with a real box on it, under a low light: a floating box's shadow, a turned box and
// a sphere standing on the ground (contacts, shadows across the ground and onto the real box).
TEST(Shadows, TheCulledDarkeningEqualsTheWholeBuffersShading)
{
    // From (0.45, -0.55, 0.5) m towards (0, 0.05, 0): x right, y down, z forward.
    const glm::dvec3 eye(0.45, -0.55, 0.5), forward = glm::normalize(glm::dvec3(0.0, 0.05, 0.0) - eye);
    const glm::dvec3 right = glm::normalize(glm::cross(forward, glm::dvec3(0.0, 0.0, 1.0)));
    const glm::dvec3 down = glm::cross(forward, right);
    glm::dmat4 cameraFromWorld(1.0);
    for (int c = 0; c < 3; ++c) {
        cameraFromWorld[c][0] = right[c];
        cameraFromWorld[c][1] = down[c];
        cameraFromWorld[c][2] = forward[c];
    }
    cameraFromWorld[3] = glm::dvec4(-glm::dot(right, eye), -glm::dot(down, eye), -glm::dot(forward, eye), 1.0);
    const auto at = [&](const glm::dvec3& centre, const glm::dvec3& size, double headingDeg) {
        const double h = headingDeg * kPi / 180.0;
        glm::dmat4 m(1.0);
        m[0] = glm::dvec4(size.x * std::cos(h), size.x * std::sin(h), 0.0, 0.0);
        m[1] = glm::dvec4(-size.y * std::sin(h), size.y * std::cos(h), 0.0, 0.0);
        m[2] = glm::dvec4(0.0, 0.0, size.z, 0.0);
        m[3] = glm::dvec4(centre, 1.0);
        return cameraFromWorld * m;
    };
    std::vector<Image8> images;
    for (int scale : {1, 4})
        for (bool cull : {true, false}) {
            RenderOptions options = shadowsOn();
            options.shadows.receiverScale = scale;
            options.shadows.cullReceivers = cull;
            LUMAR_RENDERER_OR_SKIP(renderer, kWidth, kHeight, options);
            renderer.setEnvironment(test::uniformEnvironment(1.0f), 1.0f);
            renderer.setEnvironmentRotation(environmentFromWorld() * glm::dmat3(glm::inverse(cameraFromWorld)));
            renderer.setLight(light(worldDirection(30.0, 140.0), 2.0f));
            const ModelId cube = renderer.addModel(makeCube());
            const ModelId sphere = renderer.addModel(makeUvSphere(24, 12));
            const DrawItem items[] = {
                {cube, at({0.0, 0.0, -0.01}, {1.2, 1.2, 0.02}, 0.0), -1, true},     // the ground
                {cube, at({-0.12, 0.1, 0.04}, {0.08, 0.08, 0.08}, 10.0), -1, true}, // a real box
                {cube, at({0.05, -0.05, 0.2}, {0.06, 0.1, 0.02}, 25.0), -1},        // floating
                {cube, at({0.1, 0.12, 0.03}, {0.12, 0.05, 0.06}, 30.0), -1},        // standing, turned
                {sphere, at({-0.05, -0.12, 0.04}, glm::dvec3(0.08), 0.0), -1},
            };
            images.push_back(renderOverGrey(renderer, items));
        }
    for (int scale = 0; scale < 2; ++scale) {
        const Image8& culled = images[size_t(2 * scale)];
        const Image8& whole = images[size_t(2 * scale + 1)];
        int darkened = 0, differing = 0;
        for (int y = 0; y < kHeight; ++y)
            for (int x = 0; x < kWidth; ++x)
                for (int c = 0; c < 3; ++c) {
                    const int d = std::abs(int(culled.at(x, y)[c]) - int(whole.at(x, y)[c]));
                    differing += d > 1;
                    EXPECT_LE(d, 1) << "scale " << (scale ? 4 : 1) << " at " << x << "," << y;
                    darkened += c == 1 && whole.at(x, y)[c] < kGrey - 4;
                    if (differing > 10)
                        return;
                }
        EXPECT_GT(darkened, 1500) << "too little darkening to compare";
    }
}

// At a fraction of the frame's resolution the darkening is upsampled depth-aware: a real box
// (a phantom, 0.1 m tall, its left edge at x = 0.021) stands on the ground phantom, and a
// floating box's shadow on the ground runs up to the box's edge, while on the box's top (a
// plane 0.1 m higher) the same shadow falls 4.7 cm short of it. At full, half and quarter
// resolution (240 x 160: quarter stays quarter) the box's top beside the shadow stays the
// camera image (+-1) and the ground in the shadow beside the box keeps the umbra's value: a
// plain bilinear filter would carry the shadow a texel (4 pixels) onto the box and lighten
// the ground's last texel. (The box's foot is kept off the texels' centres: where a texel's
// centre lies on the line where two receivers meet, both meet its depth and both darken it.)
TEST(Shadows, TheUpsampledDarkeningKeepsToItsSurfaceAtADepthEdge)
{
    constexpr int width = 240, height = 160;
    constexpr double cx = 119.5, cy = 79.5;
    const CameraIntrinsics k = test::makeIntrinsics(width, height, kFocal, kFocal, cx, cy);
    const auto pixelAt = [&](const glm::dvec3& p) {
        const glm::dvec3 c(cameraFromWorld() * glm::dvec4(p, 1.0));
        return glm::dvec2(cx + kFocal * c.x / c.z, cy + kFocal * c.y / c.z);
    };
    const glm::dvec3 towardsLight = worldDirection(60.0, 180.0); // from -x: shadows fall towards +x
    const double expected = umbraCode();
    for (int scale : {1, 2, 4}) {
        RenderOptions options = shadowsOn();
        options.shadows.receiverScale = scale;
        LUMAR_RENDERER_OR_SKIP(renderer, width, height, options);
        prepare(renderer, 1.0f);
        renderer.setLight(light(towardsLight, 2.0f));
        const ModelId cube = renderer.addModel(makeCube());
        // The caster spans x in [-0.27, -0.17], z in [0.25, 0.35]: its shadow covers x in
        // [-0.126, 0.032] on the ground, [-0.184, -0.026] on the box's top.
        const DrawItem items[] = {groundPhantom(cube),
                                  {cube, placed({0.071, 0.0, 0.05}, {0.1, 0.2, 0.1}), -1, true},
                                  {cube, placed({-0.22, 0.0, 0.3}, glm::dvec3(0.1)), -1}};
        renderer.render(test::solidImage(width, height, kGrey, kGrey, kGrey), k, items);
        Image8 out;
        renderer.readback(out);
        const int boxEdge = int(std::ceil(pixelAt({0.021, 0.0, 0.1}).x));     // the top's first column
        const int groundEdge = int(std::floor(pixelAt({0.021, 0.0, 0.0}).x)); // the ground's last
        ASSERT_LT(groundEdge, boxEdge);
        const int rowLow = int(std::lround(pixelAt({0.0, 0.03, 0.0}).y));
        const int rowHigh = int(std::lround(pixelAt({0.0, -0.03, 0.0}).y));
        for (int y = rowLow; y <= rowHigh; ++y) {
            for (int x = boxEdge; x < boxEdge + 10; ++x)
                ASSERT_NEAR(out.at(x, y)[1], kGrey, 1) << "box top at " << x << "," << y << ", scale " << scale;
            for (int x = groundEdge - 8; x <= groundEdge; ++x)
                ASSERT_NEAR(out.at(x, y)[1], expected, 3.0) << "ground at " << x << "," << y << ", scale " << scale;
        }
    }
}

// Where the phantom is the darkening buffer's one receiver (one convex phantom, no
// receiver-only surface), the apply pass weighs the texels by whether they hold a receiver
// instead of by their distance, in one filtered lookup of the ratio premultiplied by that
// coverage (shadow_apply.frag's APPLY_ONE_SURFACE): at quarter resolution, with a phantom slab
// whose edge runs through the floating box's umbra, the frame equals the one drawn with a
// receiver-only quad out of view added, which takes the general filter (+-1: the filtered
// lookup rounds once more), and the slab's last pixels in the umbra keep its value (a plain
// bilinear filter would take the ratio of 1 of the texels beside the slab and lighten them).
TEST(Shadows, TheOneSurfaceApplyEqualsTheDistanceAwareFilter)
{
    constexpr int width = 240, height = 160; // quarter stays quarter
    constexpr double cx = 119.5, cy = 79.5;
    const CameraIntrinsics k = test::makeIntrinsics(width, height, kFocal, kFocal, cx, cy);
    const auto pixelAt = [&](const glm::dvec3& p) {
        const glm::dvec3 c(cameraFromWorld() * glm::dvec4(p, 1.0));
        return glm::dvec2(cx + kFocal * c.x / c.z, cy + kFocal * c.y / c.z);
    };
    const glm::dvec3 shadowCentre = floatingBoxShadowCentre();
    // The slab's right edge 1.3 cm past the umbra's centre (off the texels' edges).
    const double edge = shadowCentre.x + 0.013;
    std::vector<Image8> images;
    for (bool general : {false, true}) {
        RenderOptions options = shadowsOn();
        options.shadows.receiverScale = 4;
        LUMAR_RENDERER_OR_SKIP(renderer, width, height, options);
        const ModelId cube = prepareFloatingBox(renderer);
        std::vector<DrawItem> items = {{cube, placed({edge - 0.3, 0.0, -0.01}, {0.6, 0.6, 0.02}), -1, true},
                                       {cube, placed(floatingBoxCentre(), glm::dvec3(0.1)), -1}};
        if (general) {
            const ModelId plane = renderer.addModel(groundQuad());
            items.push_back({plane, cameraFromWorld() * glm::translate(glm::dmat4(1.0), glm::dvec3(5.0, 0.0, 0.0)), -1,
                             true, true});
        }
        renderer.render(test::solidImage(width, height, kGrey, kGrey, kGrey), k, items);
        images.emplace_back();
        renderer.readback(images.back());
    }
    int darkened = 0;
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x)
            for (int c = 0; c < 3; ++c) {
                darkened += c == 1 && images[1].at(x, y)[c] < kGrey - 10;
                ASSERT_NEAR(images[0].at(x, y)[c], images[1].at(x, y)[c], 1) << "at " << x << "," << y;
            }
    EXPECT_GT(darkened, 200);
    const int last = int(std::floor(pixelAt({edge, 0.0, 0.0}).x)); // the slab's last column
    const int rowLow = int(std::lround(pixelAt({0.0, 0.03, 0.0}).y));
    const int rowHigh = int(std::lround(pixelAt({0.0, -0.03, 0.0}).y));
    for (int y = rowLow; y <= rowHigh; ++y) {
        for (int x = last - 6; x <= last; ++x)
            ASSERT_NEAR(images[0].at(x, y)[1], umbraCode(), 3.0) << "slab at " << x << "," << y;
        for (int x = last + 2; x < last + 8; ++x)
            ASSERT_NEAR(images[0].at(x, y)[1], kGrey, 1) << "beside the slab at " << x << "," << y;
    }
}

// The apply pass writes a phantom's depth itself (GL_LESS) only where each pixel meets one
// phantom fragment (ShadowPass::applyCanWriteDepth); elsewhere it darkens only the nearest
// surface (GL_EQUAL against a depth pass). In the floating box's umbra (as above), a second
// phantom on the ground, and a single phantom made of two stacked quads (not convex: from
// above each pixel of the small one meets both), are darkened once: their tops show the
// umbra's value, not its square (128 -> 89, twice 62).
TEST(Shadows, OverlappingPhantomSurfacesAreDarkenedOnce)
{
    const glm::dvec3 shadowCentre = floatingBoxShadowCentre();
    const double expected = umbraCode();
    // Tops 2 cm above the ground: the umbra moves 1.2 cm towards the light on them.
    const glm::dvec3 onTop = shadowCentre + glm::dvec3(0.02 / std::tan(kPi / 3.0), 0.0, 0.02);
    for (const bool oneModel : {false, true}) {
        LUMAR_RENDERER_OR_SKIP(renderer, kWidth, kHeight, shadowsOn());
        const ModelId cube = prepareFloatingBox(renderer);
        std::vector<DrawItem> items{{cube, placed(floatingBoxCentre(), glm::dvec3(0.1)), -1}};
        if (oneModel) {
            const auto quad = [](float half, float z) {
                return test::makeQuad({glm::vec3(-half, -half, z), glm::vec3(half, -half, z), glm::vec3(half, half, z),
                                       glm::vec3(-half, half, z)},
                                      GltfMaterial{});
            };
            GltfModel stacked = quad(0.6f, 0.0f);
            stacked.primitives.push_back(quad(0.05f, 0.02f).primitives[0]);
            stacked.boundsMax.z = 0.02f;
            const glm::dmat4 shift = glm::translate(glm::dmat4(1.0), glm::dvec3(onTop.x, onTop.y, 0.0));
            items.push_back({renderer.addModel(stacked), cameraFromWorld() * shift, -1, true});
        } else {
            items.push_back(groundPhantom(cube));
            items.push_back({cube, placed({onTop.x, onTop.y, 0.01}, {0.1, 0.1, 0.02}), -1, true});
        }
        const Image8 out = renderOverGrey(renderer, items);
        for (const glm::dvec3& offset : {glm::dvec3(0.0), glm::dvec3(0.02, 0.0, 0.0), glm::dvec3(0.0, 0.02, 0.0)})
            EXPECT_NEAR(code(out, pixelOf(onTop + offset)), expected, 3.0)
                << (oneModel ? "one model" : "two phantoms") << ", top at " << offset.x << "," << offset.y;
        // The ground beside the top (which spans x -0.038 to 0.062 from the umbra's centre, the
        // umbra -0.079 to 0.079), in the umbra too.
        EXPECT_NEAR(code(out, pixelOf(shadowCentre + glm::dvec3(-0.06, 0.0, 0.0))), expected, 3.0)
            << (oneModel ? "one model" : "two phantoms");
    }
}

// Where the apply pass writes the ground phantom's depth itself (one convex phantom), the
// depth is there for the virtual objects drawn next: a bright quad 5 cm under the ground, in
// the floating box's umbra, stays hidden, and the ground shows the umbra's value.
TEST(Shadows, TheApplyPassWritesThePhantomsDepthWhereItDarkens)
{
    LUMAR_RENDERER_OR_SKIP(renderer, kWidth, kHeight, shadowsOn());
    const ModelId cube = prepareFloatingBox(renderer);
    const glm::dvec3 boxCentre = floatingBoxCentre();
    const glm::dvec3 shadowCentre = floatingBoxShadowCentre();
    GltfMaterial white;
    white.baseColorFactor = glm::vec4(1.0f);
    const ModelId under =
        renderer.addModel(test::makeQuad({glm::vec3(-0.03f, -0.03f, 0.0f), glm::vec3(0.03f, -0.03f, 0.0f),
                                          glm::vec3(0.03f, 0.03f, 0.0f), glm::vec3(-0.03f, 0.03f, 0.0f)},
                                         white));
    const glm::dmat4 belowGround =
        cameraFromWorld() * glm::translate(glm::dmat4(1.0), shadowCentre - glm::dvec3(0.0, 0.0, 0.05));
    const double expected = umbraCode();
    const DrawItem items[] = {
        groundPhantom(cube), {cube, placed(boxCentre, glm::dvec3(0.1)), -1}, {under, belowGround, -1}};
    const Image8 out = renderOverGrey(renderer, items);
    for (const glm::dvec3& offset : {glm::dvec3(0.0), glm::dvec3(0.02, 0.0, 0.0), glm::dvec3(0.0, 0.02, 0.0)})
        EXPECT_NEAR(code(out, pixelOf(shadowCentre + offset)), expected, 3.0)
            << "ground at " << offset.x << "," << offset.y;
    // Without the ground the quad shows there, brighter than the camera image.
    const DrawItem quadAlone[] = {{cube, placed(boxCentre, glm::dvec3(0.1)), -1}, {under, belowGround, -1}};
    const Image8 seen = renderOverGrey(renderer, quadAlone);
    EXPECT_GT(code(seen, pixelOf(shadowCentre)), kGrey + 20);
}

TEST(Shadows, TheShadowMovesWithTheLight)
{
    LUMAR_RENDERER_OR_SKIP(renderer, kWidth, kHeight, shadowsOn());
    prepare(renderer, 1.0f);
    const ModelId cube = renderer.addModel(makeCube());
    const DrawItem items[] = {groundPhantom(cube), {cube, placed({0.0, 0.0, 0.3}, glm::dvec3(0.1)), -1}};
    // Light from +x: the shadow falls towards -x (image left of the box).
    renderer.setLight(light(worldDirection(60.0, 0.0), 2.0f));
    int fromX = 0, fromY = 0;
    const glm::dvec2 centroidX = darkCentroid(renderOverGrey(renderer, items), &fromX);
    // Light from +y: the shadow falls towards -y (image below the box, larger rows).
    renderer.setLight(light(worldDirection(60.0, 90.0), 2.0f));
    const glm::dvec2 centroidY = darkCentroid(renderOverGrey(renderer, items), &fromY);
    ASSERT_GT(fromX, 200);
    ASSERT_GT(fromY, 200);
    // The box centre's shadow lies 0.173 m from the origin on the ground: 43 px.
    const glm::dvec2 origin = pixelOf({0.0, 0.0, 0.0});
    EXPECT_NEAR(centroidX.x, origin.x - 43.3, 6.0);
    EXPECT_NEAR(centroidX.y, origin.y, 3.0);
    EXPECT_NEAR(centroidY.x, origin.x, 3.0);
    EXPECT_NEAR(centroidY.y, origin.y + 43.3, 6.0);
}

// Two virtual spheres (radius 0.1) under a uniform sky L = 0.5, the light (intensity 1) 45
// degrees above +x. The caster sits 0.35 m towards the light from the receiver, so the
// receiver's point facing the light (n = l) is in full umbra. There the diffuse irradiance
// drops from E_env = 0.5 pi to E_env - E_L = 0.5 pi - 1: the white receiver's radiance drops
// by rho_d E_L / pi = 0.318 (its specular part stays), from about 0.52 to 0.20.
TEST(Shadows, OneVirtualSphereShadowsAnother)
{
    LUMAR_RENDERER_OR_SKIP(renderer, kWidth, kHeight, shadowsOn());
    prepare(renderer, 0.5f);
    const glm::dvec3 towardsLight = worldDirection(45.0, 0.0);
    renderer.setLight(light(towardsLight, 1.0f));
    GltfModel sphere = makeUvSphere(48, 24);
    sphere.materials[0].baseColorFactor = glm::vec4(1.0f);
    sphere.materials[0].metallicFactor = 0.0f;
    sphere.materials[0].roughnessFactor = 1.0f;
    const ModelId model = renderer.addModel(sphere);
    const glm::dvec3 centre(0.0, 0.0, 0.1);
    const DrawItem receiver{model, placed(centre, glm::dvec3(0.2)), -1};
    const DrawItem both[] = {receiver, {model, placed(centre + 0.35 * towardsLight, glm::dvec3(0.2)), -1}};
    const glm::dvec2 facingLight = pixelOf(centre + 0.1 * towardsLight);

    const Image8 lit = renderOverGrey(renderer, {&receiver, 1});
    const Image8 shadowed = renderOverGrey(renderer, both);
    // Back to linear radiance through the camera response and sRGB, by bisection.
    const auto radianceOf = [](int value) {
        double low = 0.0, high = 16.0;
        for (int i = 0; i < 60; ++i) {
            const double mid = 0.5 * (low + high);
            (255.0 * test::srgbEncode(test::cameraResponse(mid)) < value ? low : high) = mid;
        }
        return 0.5 * (low + high);
    };
    const double litRadiance = radianceOf(code(lit, facingLight));
    const double shadowedRadiance = radianceOf(code(shadowed, facingLight));
    EXPECT_NEAR(litRadiance, 0.52, 0.03);
    // Stated: the drop is rho_d E_L / pi = 1 / pi within 0.03 (a code value is ~0.005 here).
    EXPECT_NEAR(litRadiance - shadowedRadiance, 1.0 / kPi, 0.03);
}

// The shadow takes the light's share out of the diffuse irradiance only: a surface without
// a diffuse reflectance (rho_d = 0: a metal, glass) looks the same in the other sphere's
// shadow as lit, to the code value (mesh.frag leaves its shadow out, HAS_DIFFUSE), while its
// specular reflection of the sky still shows; a rho_d of 0.5 is darkened by rho_d E_L / pi.
TEST(Shadows, OnlyTheDiffuseTermIsShadowed)
{
    LUMAR_RENDERER_OR_SKIP(renderer, kWidth, kHeight, shadowsOn());
    prepare(renderer, 0.5f);
    const glm::dvec3 towardsLight = worldDirection(45.0, 0.0);
    renderer.setLight(light(towardsLight, 1.0f));
    const glm::dvec3 centre(0.0, 0.0, 0.1);
    const glm::dvec2 facingLight = pixelOf(centre + 0.1 * towardsLight);
    const auto centreCodes = [&](float diffuse) {
        renderer.removeModels();
        GltfModel sphere = makeUvSphere(48, 24);
        sphere.materials[0].baseColorFactor = glm::vec4(diffuse, diffuse, diffuse, 1.0f);
        sphere.materials[0].metallicFactor = 0.0f;
        sphere.materials[0].roughnessFactor = 0.5f;
        const ModelId model = renderer.addModel(sphere);
        const DrawItem receiver{model, placed(centre, glm::dvec3(0.2)), -1};
        const DrawItem both[] = {receiver, {model, placed(centre + 0.35 * towardsLight, glm::dvec3(0.2)), -1}};
        return glm::ivec2(code(renderOverGrey(renderer, {&receiver, 1}), facingLight),
                          code(renderOverGrey(renderer, both), facingLight));
    };
    const glm::ivec2 specularOnly = centreCodes(0.0f);
    EXPECT_GT(specularOnly.x, 10); // the dielectric's reflection of the sky
    EXPECT_EQ(specularOnly.y, specularOnly.x);
    const glm::ivec2 diffuse = centreCodes(0.5f);
    EXPECT_LT(diffuse.y, diffuse.x - 10);
}

// mesh.vert interpolates the shadow map coordinates and the normal offset's share per unit of
// normal (the light's projection is affine), where mesh.frag computed them per pixel; normal-
// mapped materials keep the per-pixel path. A normal map that turns nothing (scale 1e-6) thus
// shades by the per-pixel coordinates, and the frame must be the same within 1 code value.
// The scene: a white sphere in another's shadow (the penumbra crosses its curved surface,
// where the interpolated normal is shorter than 1) above a double-sided white quad seen from
// behind, lit on that side (the normal offset turns round with the normal on back faces, or
// the quad shadows itself).
TEST(Shadows, InterpolatedShadowCoordinatesShadeAsThePixelsOwn)
{
    const auto whiteDiffuse = [](GltfModel model, bool normalMapped) {
        GltfMaterial& material = model.materials[0];
        material.baseColorFactor = glm::vec4(1.0f);
        material.metallicFactor = 0.0f;
        material.roughnessFactor = 1.0f;
        material.doubleSided = true;
        if (normalMapped) {
            GltfTexture flat{Image8(4, 4, 4), false};
            for (size_t i = 0; i < flat.image.data.size(); i += 4) {
                flat.image.data[i] = 128;
                flat.image.data[i + 1] = 128;
                flat.image.data[i + 2] = 255;
                flat.image.data[i + 3] = 255;
            }
            model.textures.push_back(flat);
            material.normalTexture = int(model.textures.size()) - 1;
            material.normalScale = 1e-6f;
        }
        return model;
    };
    // Facing -z (away from the camera above it): its back face is seen and lit.
    const GltfModel quad = test::makeQuad({glm::vec3(-0.5f, 0.5f, 0.0f), glm::vec3(0.5f, 0.5f, 0.0f),
                                           glm::vec3(0.5f, -0.5f, 0.0f), glm::vec3(-0.5f, -0.5f, 0.0f)},
                                          GltfMaterial{});
    const glm::dvec3 towardsLight = worldDirection(50.0, 20.0);
    Image8 images[2];
    for (int normalMapped = 0; normalMapped < 2; ++normalMapped) {
        LUMAR_RENDERER_OR_SKIP(renderer, kWidth, kHeight, shadowsOn());
        prepare(renderer, 0.5f);
        renderer.setLight(light(towardsLight, 1.5f));
        const ModelId sphere = renderer.addModel(whiteDiffuse(makeUvSphere(48, 24), normalMapped != 0));
        const ModelId ground = renderer.addModel(whiteDiffuse(quad, normalMapped != 0));
        const glm::dvec3 centre(0.0, 0.0, 0.12);
        const DrawItem items[] = {{ground, placed({0.0, 0.0, 0.0}, {0.6, 0.6, 1.0}), -1},
                                  {sphere, placed(centre, glm::dvec3(0.2)), -1},
                                  {sphere, placed(centre + 0.3 * towardsLight, glm::dvec3(0.15)), -1}};
        images[normalMapped] = renderOverGrey(renderer, items);
    }
    // The shadows are in view: the lower sphere's on the quad (an ellipse about the point below
    // its centre along the light, 0.13 m long away from the light), 7 cm beyond the sphere's rim.
    const glm::dvec3 below = glm::dvec3(0.0, 0.0, 0.12) - (0.12 / towardsLight.z) * towardsLight;
    const glm::dvec3 onQuad = below - 0.07 * glm::normalize(glm::dvec3(towardsLight.x, towardsLight.y, 0.0));
    EXPECT_LT(code(images[0], pixelOf(onQuad)), code(images[0], pixelOf({-0.25, -0.25, 0.0})) - 20);
    EXPECT_LE(test::maxCodeDifference(images[0], images[1]), 1);
}

// Convex objects cannot shadow themselves where they face the light: a sphere alone, and the
// ground around a floating box outside its shadow, look as with shadows off (no acne).
TEST(Shadows, NoShadowAcneOnAConvexObject)
{
    LUMAR_RENDERER_OR_SKIP(on, kWidth, kHeight, shadowsOn());
    LUMAR_RENDERER_OR_SKIP(off, kWidth, kHeight);
    GltfModel sphere = makeUvSphere(48, 24);
    sphere.materials[0].metallicFactor = 0.0f;
    sphere.materials[0].roughnessFactor = 1.0f;
    Image8 images[2];
    SceneRenderer* renderers[] = {&on, &off};
    for (int r = 0; r < 2; ++r) {
        prepare(*renderers[r], 0.5f);
        renderers[r]->setLight(light(worldDirection(30.0, 20.0), 1.0f));
        const DrawItem item{renderers[r]->addModel(sphere), placed({0.0, 0.0, 0.1}, glm::dvec3(0.3)), -1};
        images[r] = renderOverGrey(*renderers[r], {&item, 1});
    }
    EXPECT_LE(test::maxCodeDifference(images[0], images[1]), 1);
}

// With shadows off, a light set changes nothing: the frame is today's (the phantom depth-only,
// the camera image bit-exact through it), for phantoms, virtual objects and the ground alike.
TEST(Shadows, OffLeavesTheFrameAsWithoutShadows)
{
    RenderOptions options;
    options.shadows.enabled = false;
    LUMAR_RENDERER_OR_SKIP(withLight, kWidth, kHeight, options);
    LUMAR_RENDERER_OR_SKIP(plain, kWidth, kHeight);
    Image8 images[2];
    SceneRenderer* renderers[] = {&withLight, &plain};
    for (int r = 0; r < 2; ++r) {
        prepare(*renderers[r], 0.7f);
        if (r == 0)
            renderers[r]->setLight(light(worldDirection(50.0, 30.0), 1.5f));
        const ModelId cube = renderers[r]->addModel(makeCube());
        const ModelId plane = renderers[r]->addModel(groundQuad());
        const DrawItem items[] = {groundPhantom(cube),
                                  {cube, placed({0.0, 0.0, 0.05}, glm::dvec3(0.1)), -1},
                                  {plane, placed({0.0, 0.0, 0.0}, {0.8, 0.8, 1.0}), -1, true, true}};
        images[r] = renderOverGrey(*renderers[r], items);
    }
    EXPECT_LE(test::maxCodeDifference(images[0], images[1]), 1);
    // The ground around the box is the camera image, exactly.
    EXPECT_EQ(code(images[0], pixelOf({-0.07, 0.0, 0.0})), kGrey);
}

// Contact darkening under a diffuse sky with no light: a 0.1 m box standing on a receiver-only
// ground plane. Next to its base (7 cm from its centre) the ground sees the box's equal-volume
// sphere (radius 0.062, centre 0.05 m up) at d = 1.39 radii, 36 degrees above the horizon:
// it blocks cos(54 deg) / d^2 = 0.30 of the sky (0.21 with the fade-out window), so the
// linear value drops to about 0.79 and the encoded one to 0.79^(1/2.2) = 0.90 of the far
// ground's. Stated: between 0.80 and 0.92. Far away (0.4 m) the ground is the camera image.
TEST(Shadows, ContactDarkeningUnderADiffuseSky)
{
    LUMAR_RENDERER_OR_SKIP(renderer, kWidth, kHeight, shadowsOn());
    prepare(renderer, 1.0f); // no light set: contact darkening alone
    const ModelId cube = renderer.addModel(makeCube());
    const ModelId plane = renderer.addModel(groundQuad());
    const DrawItem scene[] = {{cube, placed({0.0, 0.0, 0.05}, glm::dvec3(0.1)), -1},
                              {plane, placed({0.0, 0.0, 0.0}, {1.0, 1.0, 1.0}), -1, true, true}};
    const Image8 out = renderOverGrey(renderer, scene);
    const int near = code(out, pixelOf({-0.07, 0.0, 0.0}));
    const int far = code(out, pixelOf({-0.35, 0.0, 0.0}));
    EXPECT_EQ(far, kGrey);
    EXPECT_GT(double(near) / far, 0.80) << near << " vs " << far;
    EXPECT_LT(double(near) / far, 0.92) << near << " vs " << far;
    // Symmetric about the box, and fading with distance.
    EXPECT_NEAR(code(out, pixelOf({0.07, 0.0, 0.0})), near, 1);
    EXPECT_GT(code(out, pixelOf({-0.12, 0.0, 0.0})), near);
}

// The shadow map is kept from frame to frame while nothing it depends on changes: it is fitted
// and drawn in a frame that moves with the scene, not with the camera (ShadowPass::render).
// The scene: two boxes over the ground phantom; the camera then turns (8 degrees) and steps
// (6 cm), everything (the items, the environment's rotation) following it.
glm::dmat4 cameraStep()
{
    const glm::dmat4 turn = glm::rotate(glm::dmat4(1.0), 8.0 * kPi / 180.0, glm::normalize(glm::dvec3(1.0, 2.0, 0.5)));
    return glm::translate(glm::dmat4(1.0), glm::dvec3(0.03, -0.02, 0.05)) * turn;
}

// The camera moved by `step` (in its own frame): the environment turns with it.
void viewFrom(SceneRenderer& renderer, const glm::dmat4& step)
{
    renderer.setEnvironmentRotation(environmentFromWorld() * glm::dmat3(glm::inverse(step * cameraFromWorld())));
}

std::vector<DrawItem> twoBoxesOnTheGround(ModelId cube, const glm::dmat4& step)
{
    std::vector<DrawItem> items = {groundPhantom(cube),
                                   {cube, placed({0.0, 0.0, 0.3}, glm::dvec3(0.1)), -1},
                                   {cube, placed({0.1, 0.05, 0.1}, {0.05, 0.08, 0.2}), -1}};
    for (DrawItem& item : items)
        item.cameraFromModel = step * item.cameraFromModel;
    return items;
}

double mapDrawn(SceneRenderer& renderer, std::span<const DrawItem> items, Image8* out = nullptr)
{
    const Image8 image = renderOverGrey(renderer, items);
    if (out)
        *out = image;
    return renderer.lastStats().shadowMapDrawn;
}

TEST(Shadows, TheMapIsKeptWhileOnlyTheCameraMovesAndShadowsAsIfDrawnAgain)
{
    LUMAR_RENDERER_OR_SKIP(renderer, kWidth, kHeight, shadowsOn());
    prepare(renderer, 1.0f);
    renderer.setLight(light(worldDirection(55.0, 20.0), 2.0f));
    ModelId cube = renderer.addModel(makeCube());
    EXPECT_EQ(mapDrawn(renderer, twoBoxesOnTheGround(cube, glm::dmat4(1.0))), 1.0);
    EXPECT_EQ(mapDrawn(renderer, twoBoxesOnTheGround(cube, glm::dmat4(1.0))), 0.0);
    // The camera moves: the map is kept, seen from where the camera now is.
    viewFrom(renderer, cameraStep());
    Image8 kept;
    EXPECT_EQ(mapDrawn(renderer, twoBoxesOnTheGround(cube, cameraStep()), &kept), 0.0);
    // The same view with the map drawn afresh (the models uploaded again).
    renderer.removeModels();
    cube = renderer.addModel(makeCube());
    Image8 fresh;
    EXPECT_EQ(mapDrawn(renderer, twoBoxesOnTheGround(cube, cameraStep()), &fresh), 1.0);
    int darkened = 0;
    for (int y = 0; y < kHeight; ++y)
        for (int x = 0; x < kWidth; ++x)
            darkened += fresh.at(x, y)[1] < kGrey - 10;
    EXPECT_GT(darkened, 300) << "the shadows are in view";
    EXPECT_LE(test::maxCodeDifference(kept, fresh), 1);
}

TEST(Shadows, TheMapIsDrawnAgainWhenACasterMovesTheLightTurnsOrTheReceiversMove)
{
    LUMAR_RENDERER_OR_SKIP(renderer, kWidth, kHeight, shadowsOn());
    prepare(renderer, 1.0f);
    renderer.setLight(light(worldDirection(55.0, 20.0), 2.0f));
    const ModelId cube = renderer.addModel(makeCube());
    std::vector<DrawItem> items = twoBoxesOnTheGround(cube, glm::dmat4(1.0));
    EXPECT_EQ(mapDrawn(renderer, items), 1.0);
    EXPECT_EQ(mapDrawn(renderer, items), 0.0);
    // A caster moves by 1 mm (the other one, not the stable frame's origin).
    items[2].cameraFromModel = glm::translate(glm::dmat4(1.0), glm::dvec3(0.001, 0.0, 0.0)) * items[2].cameraFromModel;
    EXPECT_EQ(mapDrawn(renderer, items), 1.0);
    EXPECT_EQ(mapDrawn(renderer, items), 0.0);
    // The first caster (the stable frame's origin) moves: the other one moved relative to it.
    items[1].cameraFromModel = glm::translate(glm::dmat4(1.0), glm::dvec3(0.0, 0.001, 0.0)) * items[1].cameraFromModel;
    EXPECT_EQ(mapDrawn(renderer, items), 1.0);
    EXPECT_EQ(mapDrawn(renderer, items), 0.0);
    // The light turns by a degree.
    renderer.setLight(light(worldDirection(56.0, 20.0), 2.0f));
    EXPECT_EQ(mapDrawn(renderer, items), 1.0);
    EXPECT_EQ(mapDrawn(renderer, items), 0.0);
    // Its colour and intensity are not in the map.
    renderer.setLight(light(worldDirection(56.0, 20.0), 1.0f));
    EXPECT_EQ(mapDrawn(renderer, items), 0.0);
    // The ground sinks by 5 cm: the map's depth range reaches it.
    items[0].cameraFromModel = placed({0.0, 0.0, -0.06}, {1.2, 1.2, 0.02});
    EXPECT_EQ(mapDrawn(renderer, items), 1.0);
    // A caster fewer.
    items.pop_back();
    EXPECT_EQ(mapDrawn(renderer, items), 1.0);
    EXPECT_EQ(mapDrawn(renderer, items), 0.0);
}

// An animated caster changes shape where it stands: each pose draws the map again (where its
// bounds, and so the light's fit, stay too), and the shadow follows the pose. The bending bar
// (tests/unit/render/animated_gltf.h), 0.2 m tall at this scale, stands in the plane y = 0 from
// 5 cm above the ground at the origin; at 1 s its upper half lies along -x.
GltfModel bendingBarModel(const test::ScratchDir& dir)
{
    GltfModel bar = loadGltfModel(test::bendingBar().write(dir, "bar"));
    bar.materials.assign(1, GltfMaterial{});
    bar.materials[0].doubleSided = true;
    return bar;
}

glm::dmat4 cameraFromBar()
{
    glm::dmat4 worldFromBar(1.0);
    worldFromBar[0] = glm::dvec4(0.1, 0.0, 0.0, 0.0);
    worldFromBar[1] = glm::dvec4(0.0, 0.0, 0.1, 0.0);
    worldFromBar[2] = glm::dvec4(0.0, -0.1, 0.0, 0.0);
    worldFromBar[3] = glm::dvec4(0.0, 0.0, 0.05, 1.0);
    return cameraFromWorld() * worldFromBar;
}

TEST(Shadows, AnAnimatedCasterDrawsTheMapWhenPosed)
{
    LUMAR_RENDERER_OR_SKIP(renderer, kWidth, kHeight, shadowsOn());
    prepare(renderer, 1.0f);
    renderer.setLight(light(worldDirection(60.0, 90.0), 2.0f));
    test::ScratchDir dir;
    const ModelId cube = renderer.addModel(makeCube());
    const ModelId animated = renderer.addModel(bendingBarModel(dir));
    // Its plane faces the light's azimuth; its bounds are the casters' and set the light's fit.
    const DrawItem items[] = {groundPhantom(cube), {animated, cameraFromBar(), -1}};
    const ClipTime rest[] = {{0, 0.0}};
    const ClipTime bent[] = {{0, 1.0}};
    renderer.poseModel(animated, rest);
    Image8 atRest, atRestAgain, whenBent;
    EXPECT_EQ(mapDrawn(renderer, items, &atRest), 1.0);
    EXPECT_EQ(mapDrawn(renderer, items, &atRestAgain), 0.0);
    renderer.poseModel(animated, bent);
    EXPECT_EQ(mapDrawn(renderer, items, &whenBent), 1.0);
    EXPECT_EQ(mapDrawn(renderer, items), 0.0);
    // A pose that leaves the bounds (and the light's fit) as they were still counts: the
    // renderer does not compare the vertices (GpuModel::poseGeneration).
    renderer.poseModel(animated, bent);
    EXPECT_GT(mapDrawn(renderer, items), 0.0);
    int shadowRest = 0, shadowBent = 0, changed = 0;
    const glm::dvec2 darkRest = darkCentroid(atRest, &shadowRest);
    const glm::dvec2 darkBent = darkCentroid(whenBent, &shadowBent);
    for (size_t i = 0; i < atRest.data.size(); ++i)
        changed += std::abs(int(atRest.data[i]) - int(atRestAgain.data[i])) > 1;
    EXPECT_EQ(changed, 0);
    ASSERT_GT(shadowRest, 50);
    ASSERT_GT(shadowBent, 50);
    // Bent, the top half's shadow lies further along -x.
    EXPECT_LT(darkBent.x, darkRest.x - 3.0) << darkRest.x << " -> " << darkBent.x;
}

// Where the light's fit stays (two boxes far apart set it: one out of view high up towards the
// light, one on the ground), an animated caster's pose draws again only the part of the map
// where it was and is, and the frame is the one drawn with the map drawn whole.
TEST(Shadows, AnAnimatedCasterDrawsItsPartOfTheMapAsTheWholeWouldBe)
{
    LUMAR_RENDERER_OR_SKIP(renderer, kWidth, kHeight, shadowsOn());
    prepare(renderer, 1.0f);
    renderer.setLight(light(worldDirection(60.0, 90.0), 2.0f));
    test::ScratchDir dir;
    const GltfModel bar = bendingBarModel(dir);
    ModelId cube = renderer.addModel(makeCube());
    ModelId animated = renderer.addModel(bar);
    const auto scene = [&] {
        return std::vector<DrawItem>{groundPhantom(cube),
                                     {cube, placed({-0.3, -0.3, 0.5}, glm::dvec3(0.05)), -1},
                                     {animated, cameraFromBar(), -1},
                                     {cube, placed({0.3, 0.25, 0.025}, glm::dvec3(0.05)), -1}};
    };
    const ClipTime rest[] = {{0, 0.0}};
    const ClipTime bent[] = {{0, 1.0}};
    renderer.poseModel(animated, rest);
    Image8 atRest, partly, whole;
    EXPECT_EQ(mapDrawn(renderer, scene(), &atRest), 1.0);
    renderer.poseModel(animated, bent);
    const double share = mapDrawn(renderer, scene(), &partly);
    EXPECT_GT(share, 0.0);
    EXPECT_LT(share, 0.5);
    // The same pose with the map drawn whole (the models uploaded again).
    renderer.removeModels();
    cube = renderer.addModel(makeCube());
    animated = renderer.addModel(bar);
    renderer.poseModel(animated, bent);
    EXPECT_EQ(mapDrawn(renderer, scene(), &whole), 1.0);
    int moved = 0;
    for (size_t i = 0; i < whole.data.size(); ++i)
        moved += std::abs(int(atRest.data[i]) - int(whole.data[i])) > 10;
    EXPECT_GT(moved, 100) << "the pose moves the shadow";
    EXPECT_LE(test::maxCodeDifference(partly, whole), 1);
}

// A model animated by its nodes alone (the milk truck's wheels turn; nothing is skinned): a pose
// draws again only where the primitives whose nodes moved were and are, not the whole model.
// Two boxes far apart set the light's fit (as in the test above), so it stays.
TEST(Shadows, ANodeAnimatedCasterDrawsOnlyWhereItsMovingPartsAre)
{
    LUMAR_RENDERER_OR_SKIP(renderer, kWidth, kHeight, shadowsOn());
    prepare(renderer, 1.0f);
    renderer.setLight(light(worldDirection(60.0, 90.0), 2.0f));
    const GltfModel truck =
        loadGltfModel(std::filesystem::path(LUMAR_SOURCE_DIR) / "daemon/assets/models/CesiumMilkTruck.glb");
    const glm::dvec3 extent = glm::dvec3(truck.boundsMax) - glm::dvec3(truck.boundsMin);
    // glTF's +y up onto the world's +z, 0.3 m long, standing on the ground at the origin.
    glm::dmat4 worldFromTruck = glm::rotate(glm::dmat4(1.0), kPi / 2.0, glm::dvec3(1, 0, 0));
    worldFromTruck = glm::scale(worldFromTruck, glm::dvec3(0.3 / std::max({extent.x, extent.y, extent.z})));
    worldFromTruck =
        glm::translate(worldFromTruck, -glm::dvec3(0.5 * (truck.boundsMin.x + truck.boundsMax.x), truck.boundsMin.y,
                                                   0.5 * (truck.boundsMin.z + truck.boundsMax.z)));
    ModelId cube = renderer.addModel(makeCube());
    ModelId animated = renderer.addModel(truck);
    const auto scene = [&] {
        return std::vector<DrawItem>{groundPhantom(cube),
                                     {cube, placed({-0.3, -0.3, 0.5}, glm::dvec3(0.05)), -1},
                                     {animated, cameraFromWorld() * worldFromTruck, -1},
                                     {cube, placed({0.3, 0.25, 0.025}, glm::dvec3(0.05)), -1}};
    };
    const ClipTime start[] = {{0, 0.0}};
    const ClipTime later[] = {{0, 0.3}};
    renderer.poseModel(animated, start);
    EXPECT_EQ(mapDrawn(renderer, scene()), 1.0);
    renderer.poseModel(animated, later);
    Image8 partly, whole;
    const double share = mapDrawn(renderer, scene(), &partly);
    std::printf("the wheels' pose drew %.3f of the map again\n", share);
    // Measured on llvmpipe: the truck's whole box is 0.098 of the map, one rectangle round both
    // axles' wheels 0.049, a rectangle round each 0.034.
    EXPECT_GT(share, 0.0);
    EXPECT_LT(share, 0.05);
    // The same pose with the map drawn whole (the models uploaded again).
    renderer.removeModels();
    cube = renderer.addModel(makeCube());
    animated = renderer.addModel(truck);
    renderer.poseModel(animated, later);
    EXPECT_EQ(mapDrawn(renderer, scene(), &whole), 1.0);
    EXPECT_LE(test::maxCodeDifference(partly, whole), 1);
}

} // namespace
} // namespace lumar
