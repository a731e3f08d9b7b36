// Phantoms carrying the camera image in the environment maps (DESIGN.md §6.1, §6.5): a chrome
// ball reflects the real table (its wood, not a flat colour), a white object next to a real
// red box turns red on that side, parts of a phantom the camera cannot see keep the
// configured colour, and the phantoms still hide virtual objects in the frame.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <vector>

#include <glm/gtc/matrix_transform.hpp>
#include <gtest/gtest.h>

#include "gl_readback.h"
#include "gl_test_support.h"
#include "gles_renderer/assets/builtin_shapes.h"
#include "gles_renderer/assets/lafortune_material.h"
#include "gles_renderer/ibl/cube_map.h"
#include "gles_renderer/ibl/lafortune_shading.h"

namespace lumar {
namespace {

constexpr int kWidth = 320, kHeight = 240;
constexpr double kFocal = 300.0;

const CameraIntrinsics& intrinsics()
{
    static const CameraIntrinsics k =
        test::makeIntrinsics(kWidth, kHeight, kFocal, kFocal, (kWidth - 1) / 2.0, (kHeight - 1) / 2.0);
    return k;
}

// The camera ray through the centre of pixel (x, y), camera frame.
glm::dvec3 pixelRay(double x, double y)
{
    const CameraIntrinsics& k = intrinsics();
    return glm::normalize(glm::dvec3((x - k.cx) / k.fx, (y - k.cy) / k.fy, 1.0));
}

glm::dvec2 project(const glm::dvec3& p)
{
    const CameraIntrinsics& k = intrinsics();
    return {k.fx * p.x / p.z + k.cx, k.fy * p.y / p.z + k.cy};
}

// Distance along `dir` from `origin` to the sphere (centre, radius), or -1.
double hitSphere(const glm::dvec3& origin, const glm::dvec3& dir, const glm::dvec3& centre, double radius)
{
    const glm::dvec3 oc = origin - centre;
    const double b = glm::dot(oc, dir);
    const double disc = b * b - (glm::dot(oc, oc) - radius * radius);
    return disc < 0.0 ? -1.0 : -b - std::sqrt(disc);
}

// Whether the camera ray `dir` meets the unit cube placed by `cameraFromBox`.
bool hitsBox(const glm::dmat4& cameraFromBox, const glm::dvec3& dir)
{
    const glm::dmat4 boxFromCamera = glm::inverse(cameraFromBox);
    const glm::dvec3 o(boxFromCamera * glm::dvec4(0, 0, 0, 1));
    const glm::dvec3 d(boxFromCamera * glm::dvec4(dir, 0));
    double near = -1e30, far = 1e30;
    for (int a = 0; a < 3; ++a) {
        if (std::abs(d[a]) < 1e-12) {
            if (std::abs(o[a]) > 0.5)
                return false;
            continue;
        }
        const double t0 = (-0.5 - o[a]) / d[a], t1 = (0.5 - o[a]) / d[a];
        near = std::max(near, std::min(t0, t1));
        far = std::min(far, std::max(t0, t1));
    }
    return near <= far && far > 0.0;
}

GltfModel chromeSphere()
{
    GltfModel model = makeUvSphere(48, 24);
    model.materials[0].hasLafortune = true;
    model.materials[0].lafortune = *materialPreset("chrome");
    return model;
}

GltfModel whiteSphere()
{
    GltfModel model = makeUvSphere(48, 24);
    model.materials[0].baseColorFactor = glm::vec4(0.9f, 0.9f, 0.9f, 1.0f);
    model.materials[0].metallicFactor = 0.0f;
    model.materials[0].roughnessFactor = 1.0f;
    return model;
}

GltfModel colouredPhantom(GltfModel model, const glm::vec3& colour)
{
    model.materials[0].baseColorFactor = glm::vec4(colour, 1.0f);
    model.materials[0].metallicFactor = 0.0f;
    model.materials[0].roughnessFactor = 1.0f;
    return model;
}

glm::dmat4 placed(const glm::dvec3& at, double size)
{
    return glm::translate(glm::dmat4(1.0), at) * glm::dmat4(glm::dmat3(size));
}

// A wood-like grain on the table (table coordinates in metres): growth rings 4 cm apart,
// warped, light and dark early and late wood (sRGB code values).
glm::dvec3 woodAt(double x, double y)
{
    const double warp =
        0.012 * std::sin(2.0 * std::numbers::pi * y / 0.25) + 0.004 * std::sin(2.0 * std::numbers::pi * y / 0.07);
    const double ring = 0.5 + 0.5 * std::sin(2.0 * std::numbers::pi * (x + warp) / 0.04);
    const glm::dvec3 early(200, 145, 90), late(105, 60, 30);
    return early + (late - early) * std::pow(ring, 1.5);
}

// The mean of a (2r+1)^2 window of `image` round (x, y), per channel.
glm::dvec3 windowMean(const Image8& image, int x, int y, int r)
{
    glm::dvec3 sum(0.0);
    int n = 0;
    for (int dy = -r; dy <= r; ++dy)
        for (int dx = -r; dx <= r; ++dx) {
            const int px = std::clamp(x + dx, 0, image.width - 1), py = std::clamp(y + dy, 0, image.height - 1);
            const uint8_t* p = image.at(px, py);
            sum += glm::dvec3(p[0], p[1], p[2]);
            ++n;
        }
    return sum / double(n);
}

// A virtual object behind a phantom with a dynamic map (so the camera image, the phantoms'
// camera depth and the maps are all drawn this frame): the phantom's pixels stay the camera's.
TEST(PhantomCamera, PhantomHidesAVirtualObjectAndLeavesTheCameraImage)
{
    LUMAR_RENDERER_OR_SKIP(renderer, kWidth, kHeight);
    renderer.setEnvironment(test::uniformEnvironment(0.3f), 1.0f);
    renderer.setExposure(1.7f);
    Image8 camera(kWidth, kHeight, 3);
    for (size_t i = 0; i < camera.data.size(); ++i)
        camera.data[i] = uint8_t((i * 37) % 251); // a busy image: any change shows
    const ModelId quad =
        renderer.addModel(test::cameraFacingRectangle(-0.4f, -0.3f, 0.4f, 0.3f, test::emissiveMaterial({1, 1, 1})));
    const ModelId box = renderer.addModel(colouredPhantom(makeCube(), {0.5f, 0.5f, 0.5f}));
    const DrawItem items[] = {{quad, test::translation(0, 0, 1), 0}, {box, placed({-0.15, 0.0, 0.5}, 0.2), -1, true}};
    for (int frame = 0; frame < 2; ++frame)
        renderer.render(camera, intrinsics(), items);
    ASSERT_NE(renderer.objectMaps(0), nullptr);
    Image8 out;
    renderer.readback(out);
    // The box spans x in [-0.25, -0.05] / 0.4 * 300 + 159.5 = [-28, 122], y within +-75 px
    // of the centre (its front face, nearest the camera, is the widest).
    int worst = 0;
    for (int y = 50; y < 190; ++y)
        for (int x = 0; x < 115; ++x)
            for (int c = 0; c < 3; ++c)
                worst = std::max(worst, std::abs(int(out.at(x, y)[c]) - int(camera.at(x, y)[c])));
    EXPECT_LE(worst, 1);
    for (int c = 0; c < 3; ++c) // beside it the quad is drawn
        EXPECT_GT(out.at(250, 120)[c], 150);
}

// A chrome ball above a table-plane phantom, the camera image showing wood on the table.
struct TableScene {
    glm::dmat4 cameraFromTable{1.0}; // table frame: z up, the table top is z = 0
    glm::dvec3 sphereCentre{0.0};    // camera frame
    double sphereRadius = 0.05;
    Image8 camera{kWidth, kHeight, 3};
    std::vector<DrawItem> items;
};

TableScene makeTableScene(SceneRenderer& renderer)
{
    TableScene scene;
    // The camera 45 cm in front of the ball and 35 cm above the table, looking at its foot.
    const glm::dvec3 eye(0.0, -0.45, 0.35), target(0.0, 0.0, 0.03), up(0.0, 0.0, 1.0);
    const glm::dvec3 z = glm::normalize(target - eye), x = glm::normalize(glm::cross(z, up)), y = glm::cross(z, x);
    glm::dmat4 tableFromCamera(1.0);
    tableFromCamera[0] = glm::dvec4(x, 0.0);
    tableFromCamera[1] = glm::dvec4(y, 0.0);
    tableFromCamera[2] = glm::dvec4(z, 0.0);
    tableFromCamera[3] = glm::dvec4(eye, 1.0);
    scene.cameraFromTable = glm::inverse(tableFromCamera);
    scene.sphereCentre = glm::dvec3(scene.cameraFromTable * glm::dvec4(0.0, 0.0, 0.08, 1.0));

    // The camera image: wood where a pixel's ray meets the 1 m table, grey beyond.
    const glm::dvec3 origin(tableFromCamera[3]);
    for (int py = 0; py < kHeight; ++py)
        for (int px = 0; px < kWidth; ++px) {
            const glm::dvec3 d = glm::dmat3(tableFromCamera) * pixelRay(px, py);
            glm::dvec3 colour(120.0);
            if (d.z < 0.0) {
                const glm::dvec3 p = origin - d * (origin.z / d.z);
                if (std::abs(p.x) <= 0.5 && std::abs(p.y) <= 0.5)
                    colour = woodAt(p.x, p.y);
            }
            for (int c = 0; c < 3; ++c)
                scene.camera.at(px, py)[c] = uint8_t(std::lround(colour[c]));
        }

    renderer.setEnvironment(test::uniformEnvironment(0.3f), 1.0f);
    const ModelId sphere = renderer.addModel(chromeSphere());
    const ModelId table = renderer.addModel(colouredPhantom(makePlane(), {0.45f, 0.25f, 0.12f}));
    // The plane is +Y up: stand it in the table plane (+Y -> +Z).
    const glm::dmat4 upright(glm::dvec4(1, 0, 0, 0), glm::dvec4(0, 0, 1, 0), glm::dvec4(0, -1, 0, 0),
                             glm::dvec4(0, 0, 0, 1));
    scene.items.push_back(
        {sphere, glm::translate(glm::dmat4(1.0), scene.sphereCentre) * glm::dmat4(glm::dmat3(2.0 * scene.sphereRadius)),
         0});
    DrawItem tableItem{table, scene.cameraFromTable * upright};
    tableItem.phantom = true;
    scene.items.push_back(tableItem);
    return scene;
}

struct ReflectedPixel {
    int x, y;             // on the ball
    glm::dvec3 seen;      // the rendered pixel
    glm::dvec3 table;     // the camera image round the table point the reflection ray meets
    glm::dvec3 reflected; // the ball's specular weight there: pixel radiance / reflected radiance
};

// The chrome's specular weight (rho_s' x the falloff g' = N.r, McAllister) for view
// direction `toViewer` at normal `n`, from the CPU twin of lafortune.glsl.
glm::dvec3 chromeWeight(const glm::dvec3& toViewer, const glm::dvec3& n)
{
    const LafortuneParams chrome = *materialPreset("chrome");
    const glm::vec3 nf(n);
    const glm::vec3 t = glm::normalize(glm::cross(nf, std::abs(nf.x) < 0.9f ? glm::vec3(1, 0, 0) : glm::vec3(0, 1, 0)));
    const glm::vec3 b = glm::cross(nf, t);
    return glm::dvec3(
        lafortuneShade(glm::vec3(toViewer), t, b, nf, chrome.lobe, chrome.exponent, chrome.specular, chrome.fresnelPhi)
            .specularWeight);
}

// The ball's pixels whose mirror direction, followed from the ball's centre (where its map
// is rendered), meets the table well inside it and inside the camera's view.
std::vector<ReflectedPixel> reflectedTablePixels(const TableScene& scene, const Image8& frame)
{
    std::vector<ReflectedPixel> pixels;
    const glm::dmat3 tableFromCamera = glm::transpose(glm::dmat3(scene.cameraFromTable));
    const glm::dvec3 tableOrigin(scene.cameraFromTable[3]);
    const glm::dvec3 tableNormal(scene.cameraFromTable[2]);
    for (int py = 0; py < kHeight; ++py)
        for (int px = 0; px < kWidth; ++px) {
            const glm::dvec3 d = pixelRay(px, py);
            const double t = hitSphere(glm::dvec3(0.0), d, scene.sphereCentre, scene.sphereRadius);
            if (t <= 0.0)
                continue;
            const glm::dvec3 n = glm::normalize(d * t - scene.sphereCentre);
            if (glm::dot(n, -d) < 0.5) // away from the silhouette (polygon edges, Fresnel)
                continue;
            const glm::dvec3 r = glm::reflect(d, n);
            if (glm::dot(r, tableNormal) > -0.35) // steeply down only: grazing views blur
                continue;
            const double s = glm::dot(tableOrigin - scene.sphereCentre, tableNormal) / glm::dot(r, tableNormal);
            const glm::dvec3 hit = scene.sphereCentre + r * s;
            const glm::dvec3 onTable = tableFromCamera * (hit - tableOrigin);
            if (std::abs(onTable.x) > 0.45 || std::abs(onTable.y) > 0.45)
                continue;
            const glm::dvec2 q = project(hit);
            if (q.x < 8 || q.y < 8 || q.x > kWidth - 9 || q.y > kHeight - 9)
                continue;
            const uint8_t* p = frame.at(px, py);
            pixels.push_back({px, py, glm::dvec3(p[0], p[1], p[2]),
                              windowMean(scene.camera, int(std::lround(q.x)), int(std::lround(q.y)), 2),
                              chromeWeight(-d, n)});
        }
    return pixels;
}

double stddev(const std::vector<double>& v)
{
    double mean = 0.0;
    for (double x : v)
        mean += x;
    mean /= double(v.size());
    double sum = 0.0;
    for (double x : v)
        sum += (x - mean) * (x - mean);
    return std::sqrt(sum / double(v.size()));
}

double correlation(const std::vector<double>& a, const std::vector<double>& b)
{
    double ma = 0.0, mb = 0.0;
    for (size_t i = 0; i < a.size(); ++i) {
        ma += a[i];
        mb += b[i];
    }
    ma /= double(a.size());
    mb /= double(b.size());
    double ab = 0.0, aa = 0.0, bb = 0.0;
    for (size_t i = 0; i < a.size(); ++i) {
        ab += (a[i] - ma) * (b[i] - mb);
        aa += (a[i] - ma) * (a[i] - ma);
        bb += (b[i] - mb) * (b[i] - mb);
    }
    return ab / std::sqrt(aa * bb);
}

TEST(PhantomCamera, ChromeBallReflectsTheTablesWood)
{
    const auto renderScene = [](bool showCamera, TableScene& scene, Image8& out) {
        RenderOptions options;
        options.environmentMaps.phantomsShowCamera = showCamera;
        auto made = test::tryCreateRenderer(kWidth, kHeight, options);
        if (!made.renderer)
            return false;
        scene = makeTableScene(*made.renderer);
        // The camera's exposure relative to the lighting: the table's radiance is the camera's
        // linear value divided by it, so the mirror shows the camera's code values again.
        made.renderer->setExposure(1.6f);
        for (int frame = 0; frame < 2; ++frame)
            made.renderer->render(scene.camera, intrinsics(), scene.items);
        made.renderer->readback(out);
        return true;
    };
    TableScene scene, flatScene;
    Image8 textured, flat;
    if (!renderScene(true, scene, textured) || !renderScene(false, flatScene, flat))
        GTEST_SKIP() << "no GLES 3 renderer";

    const std::vector<ReflectedPixel> pixels = reflectedTablePixels(scene, textured);
    ASSERT_GT(pixels.size(), 300u);
    // The code a pixel should have: the camera's value, linearised, times the chrome's
    // specular weight (0.95 x N.r, a mirror darkens towards its rim), through the response.
    // And the code of the radiance a pixel reflects (its own divided by that weight), whose
    // spread shows the texture rather than the weight's own change across the ball.
    const auto reflectedCode = [](double code, double weight) {
        return 255.0 * test::srgbEncode(test::srgbDecode(code / 255.0) / weight);
    };
    double sumError = 0.0, worst = 0.0;
    std::vector<double> seenRed, expectedRed, flatRed, cameraRed;
    for (const ReflectedPixel& p : pixels) {
        glm::dvec3 expected;
        for (int c = 0; c < 3; ++c)
            expected[c] = test::toneMappedCode(p.reflected[c] * test::srgbDecode(p.table[c] / 255.0));
        const double error = glm::length(p.seen - expected);
        sumError += error;
        worst = std::max(worst, error);
        seenRed.push_back(reflectedCode(p.seen.r, p.reflected.r));
        expectedRed.push_back(expected.r);
        cameraRed.push_back(p.table.r);
        flatRed.push_back(reflectedCode(flat.at(p.x, p.y)[0], p.reflected.r));
    }
    const double meanError = sumError / double(pixels.size());
    const double spread = stddev(seenRed), cameraSpread = stddev(cameraRed), flatSpread = stddev(flatRed);
    const double r = correlation(seenRed, cameraRed);
    std::printf("%zu ball pixels reflect the table: mean colour distance %.1f (worst %.1f) codes; reflected red "
                "spread %.1f (camera %.1f, flat phantom %.1f); correlation with the camera %.3f\n",
                pixels.size(), meanError, worst, spread, cameraSpread, flatSpread, r);
    // Within a colour distance (RGB Euclidean, code values) of the camera's pixels at the
    // point the reflection meets: the quarter-size copy, its mip level for the face texel's
    // footprint and the 64-px map blur the grain a little.
    EXPECT_LT(meanError, 12.0);
    // And they vary like the wood: what a flat-coloured phantom reflects hardly varies; what
    // this one reflects varies nearly as much as the camera's pixels, and with them.
    EXPECT_GT(spread, 5.0 * flatSpread);
    EXPECT_GT(spread, 0.6 * cameraSpread);
    EXPECT_GT(r, 0.85);
}

// A white diffuse ball beside a panel phantom (a thin box) the camera sees as saturated red:
// the ball's side facing the panel turns red (colour bleeding), its far side stays grey.
TEST(PhantomCamera, RedPanelBleedsOntoAWhiteBall)
{
    LUMAR_RENDERER_OR_SKIP(renderer, kWidth, kHeight);
    renderer.setEnvironment(test::uniformEnvironment(0.3f), 1.0f);
    const glm::dvec3 ball(-0.06, 0.0, 0.6);
    const double radius = 0.05;
    // 20 x 20 x 1 cm, turned 45 degrees about the camera's y: its face looks at both the
    // camera and the ball, so the camera sees what lights the ball.
    const glm::dmat4 cameraFromPanel = glm::translate(glm::dmat4(1.0), glm::dvec3(0.12, 0.0, 0.62)) *
                                       glm::rotate(glm::dmat4(1.0), glm::radians(45.0), glm::dvec3(0, 1, 0)) *
                                       glm::scale(glm::dmat4(1.0), glm::dvec3(0.2, 0.2, 0.01));
    Image8 camera = test::solidImage(kWidth, kHeight, 128, 128, 128);
    for (int py = 0; py < kHeight; ++py)
        for (int px = 0; px < kWidth; ++px)
            if (hitsBox(cameraFromPanel, pixelRay(px, py))) {
                uint8_t* p = camera.at(px, py);
                p[0] = 235;
                p[1] = 20;
                p[2] = 20;
            }
    const ModelId sphere = renderer.addModel(whiteSphere());
    const ModelId panel = renderer.addModel(colouredPhantom(makeCube(), {0.5f, 0.5f, 0.5f}));
    const DrawItem items[] = {{sphere, placed(ball, 2.0 * radius), 0}, {panel, cameraFromPanel, -1, true}};
    for (int frame = 0; frame < 2; ++frame)
        renderer.render(camera, intrinsics(), items);
    Image8 out;
    renderer.readback(out);
    // In linear radiance (the codes compress ratios: 1.7 in radiance is 1.25 in codes).
    const auto redOverGreen = [&](const glm::dvec3& normal) {
        const glm::dvec2 q = project(ball + radius * glm::normalize(normal));
        const glm::dvec3 c = windowMean(out, int(std::lround(q.x)), int(std::lround(q.y)), 1);
        return test::srgbDecode(c.r / 255.0) / std::max(test::srgbDecode(c.g / 255.0), 1e-3);
    };
    // Points the camera sees (normals towards it), on the panel's side and on the other.
    const double facing = redOverGreen({0.9, 0.0, -0.44}), far = redOverGreen({-0.9, 0.0, -0.44});
    std::printf("red / green: %.3f on the side facing the red panel, %.3f on the far side\n", facing, far);
    // The panel fills about 0.8 sr of the facing side's view at radiance 0.83 (red) against
    // the environment's 0.3: about 1.7 times the red irradiance, the same green.
    EXPECT_GT(facing, 1.5 * far);
    EXPECT_NEAR(far, 1.0, 0.1); // the far side sees the grey environment
}

// Where the camera cannot see a phantom — its back face, or a face hidden behind another
// phantom — a map shows the phantom's configured colour (green here, lit by the grey
// environment); where it can, the camera image (red).
TEST(PhantomCamera, PartsTheCameraCannotSeeKeepTheConfiguredColour)
{
    LUMAR_RENDERER_OR_SKIP(renderer, kWidth, kHeight);
    renderer.setEnvironment(test::uniformEnvironment(0.3f), 1.0f);
    const glm::vec3 green(0.1f, 0.7f, 0.1f);
    const ModelId box = renderer.addModel(colouredPhantom(makeCube(), green));
    const ModelId sphere = renderer.addModel(chromeSphere());
    const glm::dvec3 inFront(0.12, 0.0, 0.62), behind(0.0, 0.0, 1.0);
    // A large box B (front face at z = 0.7, back face at 0.9), a small box A in front of its
    // centre, a ball between them off to the side and one behind B.
    const DrawItem items[] = {{box, placed({0.0, 0.0, 0.8}, 0.2), -1, true},
                              {box, placed({0.0, 0.0, 0.5}, 0.06), -1, true},
                              {sphere, placed(inFront, 0.04), 0},
                              {sphere, placed(behind, 0.04), 1}};
    const Image8 camera = test::solidImage(kWidth, kHeight, 220, 30, 30);
    renderer.render(camera, intrinsics(), items);
    ASSERT_NE(renderer.objectMaps(0), nullptr);
    ASSERT_NE(renderer.objectMaps(1), nullptr);
    const IblSettings settings;
    const CubeMapF frontMap = test::readMirrorMap(*renderer.objectMaps(0), settings.mirrorSize);
    const CubeMapF backMap = test::readMirrorMap(*renderer.objectMaps(1), settings.mirrorSize);
    // The environment frame is the camera's (no rotation set): directions are camera-frame.
    const glm::vec3 hiddenCentre = sampleCubeNearest(frontMap, glm::vec3(glm::dvec3(0.0, 0.0, 0.7) - inFront));
    const glm::vec3 visibleEdge = sampleCubeNearest(frontMap, glm::vec3(glm::dvec3(0.09, 0.0, 0.7) - inFront));
    const glm::vec3 backFace = sampleCubeNearest(backMap, glm::vec3(glm::dvec3(0.0, 0.0, 0.9) - behind));
    const auto print = [](const char* what, const glm::vec3& c) {
        std::printf("%s: (%.3f, %.3f, %.3f)\n", what, c.r, c.g, c.b);
    };
    print("B's front face behind A", hiddenCentre);
    print("B's front face beside A", visibleEdge);
    print("B's back face", backFace);
    // The configured colour under uniform radiance 0.3: albedo x 0.3 plus a dielectric's
    // 4 % specular, i.e. about (0.04, 0.22, 0.04).
    for (const glm::vec3& c : {hiddenCentre, backFace}) {
        EXPECT_NEAR(c.g, green.g * 0.3f, 0.03f);
        EXPECT_LT(c.r, 0.08f);
    }
    // The camera's red, linearised (code 220 -> 0.716), where the camera saw B.
    EXPECT_NEAR(visibleEdge.r, float(test::srgbDecode(220.0 / 255.0)), 0.03f);
    EXPECT_LT(visibleEdge.g, 0.05f);
}

} // namespace
} // namespace lumar
