// Khronos glTF sample models (tests/data/khronos, MANIFEST.md there) as the renderer draws
// them: each check reads pixels of a rendered frame and measures the property the sample was
// made to show (its README's pass/fail marks, colours, a moved vertex), never a hash.
// LUMAR_KHRONOS_DUMP=DIR writes every frame rendered here as DIR/NAME.png for a look.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include <glm/gtc/matrix_transform.hpp>
#include <gtest/gtest.h>
#include <stb_image_write.h>

#include "gl_test_support.h"

namespace lumar {
namespace {

std::filesystem::path sample(const std::string& relative)
{
    return std::filesystem::path(LUMAR_TEST_DATA_DIR) / "khronos" / relative;
}

// A view of a model: the camera looks along `forward` (model space) at the centre of the
// model's bounds, `up` up the image, from where the bounds' sphere fills `fill` of the
// image's shorter side.
struct View {
    glm::dvec3 forward{0, 0, -1};
    glm::dvec3 up{0, 1, 0};
    double fill = 0.9;
};

struct Frame {
    Image8 rgb;
    glm::dmat4 cameraFromModel{1.0};
    CameraIntrinsics k;
    // The pixel (centre coordinates) where model point p appears.
    [[nodiscard]] glm::dvec2 pixelOf(const glm::dvec3& p) const
    {
        const glm::dvec3 c(cameraFromModel * glm::dvec4(p, 1.0));
        return {k.cx + k.fx * c.x / c.z, k.cy + k.fy * c.y / c.z};
    }
    [[nodiscard]] glm::ivec3 at(int x, int y) const
    {
        const uint8_t* p = rgb.at(std::clamp(x, 0, rgb.width - 1), std::clamp(y, 0, rgb.height - 1));
        return {p[0], p[1], p[2]};
    }
};

glm::dmat4 cameraFromModelFor(const glm::vec3& boundsMin, const glm::vec3& boundsMax, const View& view, double focal,
                              int size)
{
    const glm::dvec3 centre = 0.5 * (glm::dvec3(boundsMin) + glm::dvec3(boundsMax));
    const double radius = 0.5 * glm::length(glm::dvec3(boundsMax) - glm::dvec3(boundsMin));
    const double distance = radius / (view.fill * 0.5 * size / focal);
    const glm::dvec3 f = glm::normalize(view.forward);
    const glm::dvec3 r = glm::normalize(glm::cross(f, view.up)); // OpenCV: x right, y down, z forward
    const glm::dvec3 d = glm::cross(f, r);
    glm::dmat4 m(1.0);
    for (int i = 0; i < 3; ++i) {
        m[i][0] = r[i];
        m[i][1] = d[i];
        m[i][2] = f[i];
    }
    const glm::dvec3 eye = centre - distance * f;
    m[3] = glm::dvec4(-glm::dmat3(m) * eye, 1.0);
    return m;
}

void dump(const Frame& frame, const std::string& name)
{
    const char* dir = std::getenv("LUMAR_KHRONOS_DUMP");
    if (dir == nullptr)
        return;
    const std::filesystem::path file = std::filesystem::path(dir) / (name + ".png");
    stbi_write_png(file.c_str(), frame.rgb.width, frame.rgb.height, 3, frame.rgb.data.data(), frame.rgb.width * 3);
}

constexpr int kSize = 256;
constexpr double kFocal = 300.0;
const glm::ivec3 kBackground{10, 20, 30};

struct Scene {
    int size = kSize;
    double focal = kFocal;
    float environment = 0.6f;
    glm::ivec3 background = kBackground;
    // Model units to metres: the sweep shrinks or grows every model to a 1 m bounding sphere
    // (the Fox is 155 units long: seen whole from 230 m, beyond the 100 m far plane).
    double modelScale = 1.0;
};

// Renders `model` (already added as `id`, posed as the caller left it) seen as `view` says,
// over a uniform camera image, lit by a uniform environment.
Frame renderModel(SceneRenderer& renderer, ModelId id, const GltfModel& model, const View& view,
                  const std::string& name, const Scene& scene = {})
{
    renderer.setEnvironment(test::uniformEnvironment(scene.environment), 1.0f);
    Frame frame;
    frame.k = test::makeIntrinsics(scene.size, scene.size, scene.focal, scene.focal, scene.size / 2.0 - 0.5,
                                   scene.size / 2.0 - 0.5);
    const double s = scene.modelScale;
    frame.cameraFromModel =
        cameraFromModelFor(glm::vec3(s * glm::dvec3(model.boundsMin)), glm::vec3(s * glm::dvec3(model.boundsMax)), view,
                           scene.focal, scene.size) *
        glm::scale(glm::dmat4(1.0), glm::dvec3(s));
    const DrawItem item{id, frame.cameraFromModel};
    renderer.render(test::solidImage(scene.size, scene.size, uint8_t(scene.background.r), uint8_t(scene.background.g),
                                     uint8_t(scene.background.b)),
                    frame.k, {&item, 1});
    renderer.readback(frame.rgb);
    dump(frame, name);
    return frame;
}

// Pixel classes by hue, for marks drawn in saturated colours over white, grey or black.
bool isRed(const glm::ivec3& c)
{
    return c.r > c.g + 60 && c.r > c.b + 60;
}
bool isGreen(const glm::ivec3& c)
{
    return c.g > c.r + 60 && c.g > c.b + 60;
}
bool isBlue(const glm::ivec3& c)
{
    return c.b > c.r + 60 && c.b > c.g + 60;
}
// Two channels high, the third low: cyan, magenta or yellow.
bool isSecondary(const glm::ivec3& c)
{
    const int low = std::min({c.r, c.g, c.b});
    const int high = std::max({c.r, c.g, c.b});
    const int middle = c.r + c.g + c.b - low - high;
    return middle > low + 80 && high - middle < 50;
}
bool isYellow(const glm::ivec3& c)
{
    return isSecondary(c) && c.b < c.r && c.b < c.g;
}

// The pixel rectangle [x0, x1) x [y0, y1) of model-space points, shrunk by `inset` of its size
// on every side.
struct Rect {
    int x0 = 0, y0 = 0, x1 = 0, y1 = 0;
};

Rect projectedRect(const Frame& frame, const std::vector<glm::dvec3>& points, double inset)
{
    glm::dvec2 low(1e9), high(-1e9);
    for (const glm::dvec3& p : points) {
        const glm::dvec2 q = frame.pixelOf(p);
        low = glm::min(low, q);
        high = glm::max(high, q);
    }
    const glm::dvec2 margin = inset * (high - low);
    return {int(std::ceil(low.x + margin.x)), int(std::ceil(low.y + margin.y)), int(std::floor(high.x - margin.x)) + 1,
            int(std::floor(high.y - margin.y)) + 1};
}

// Model-space vertices of every primitive drawn with material `name`.
std::vector<glm::dvec3> verticesOf(const GltfModel& model, const std::string& name)
{
    std::vector<glm::dvec3> out;
    for (const GltfPrimitive& p : model.primitives) {
        if (p.material < 0 || model.materials[size_t(p.material)].name != name)
            continue;
        for (const glm::vec3& v : p.positions)
            out.emplace_back(glm::dvec3(p.modelFromMesh * glm::vec4(v, 1.0f)));
    }
    return out;
}

int count(const Frame& frame, const Rect& r, const std::function<bool(const glm::ivec3&)>& is)
{
    int n = 0;
    for (int y = r.y0; y < r.y1; ++y)
        for (int x = r.x0; x < r.x1; ++x)
            n += is(frame.at(x, y));
    return n;
}

// TextureSettingsTest: every quad shows a green check where its sampler's wrap mode is
// honoured, a red X where another mode is used (README: clamp and mirrored repeat, per axis).
TEST(KhronosRender, TextureSettingsTestShowsChecksAndNoCrosses)
{
    LUMAR_RENDERER_OR_SKIP(renderer, 512, 512);
    const GltfModel model = loadGltfModel(sample("TextureSettingsTest/TextureSettingsTest.glb"));
    const ModelId id = renderer.addModel(model);
    const Frame frame = renderModel(renderer, id, model, View{}, "TextureSettingsTest", {.size = 512, .focal = 600.0});
    for (const char* material :
         {"TextureClampMaterialS", "TextureClampMaterialT", "TextureRepeatMaterialS", "TextureRepeatMaterialT",
          "TextureMirrorMaterialS", "TextureMirrorMaterialT", "DoubleSidedMaterial", "SingleSidedMaterial"}) {
        SCOPED_TRACE(material);
        const Rect r = projectedRect(frame, verticesOf(model, material), 0.03);
        const int pixels = (r.x1 - r.x0) * (r.y1 - r.y0);
        ASSERT_GT(pixels, 2000) << "the quad is in view";
        // A check covers about a tenth of each half of a quad; an X as much.
        EXPECT_GT(count(frame, r, isGreen), pixels / 30);
        EXPECT_LT(count(frame, r, isRed), 10);
    }
}

// VertexColorTest: the top row's checks are multiplied by red, green and blue vertex colours,
// which remove the cyan, magenta and yellow X's drawn over them (README); the bottom row, white,
// shows the same checks. Measured without the label plane in front.
TEST(KhronosRender, VertexColorTestColoursCancelTheCrosses)
{
    LUMAR_RENDERER_OR_SKIP(renderer, kSize, kSize);
    GltfModel model = loadGltfModel(sample("VertexColorTest/VertexColorTest.glb"));
    std::erase_if(model.primitives,
                  [&](const GltfPrimitive& p) { return model.materials[size_t(p.material)].name == "Label_Mat"; });
    ASSERT_EQ(model.primitives.size(), 1u);
    const ModelId id = renderer.addModel(model);
    const Frame frame = renderModel(renderer, id, model, View{}, "VertexColorTest");
    const Rect all = projectedRect(frame, verticesOf(model, "VC_Checks_Mat"), 0.0);
    const int middle = (all.y0 + all.y1) / 2;
    const Rect top{all.x0, all.y0, all.x1, middle}, bottom{all.x0, middle, all.x1, all.y1};
    EXPECT_LT(count(frame, all, isSecondary), 10) << "cyan, magenta or yellow X's";
    using Is = bool (*)(const glm::ivec3&);
    for (const auto& [what, is] : {std::pair<const char*, Is>{"red", isRed}, {"green", isGreen}, {"blue", isBlue}}) {
        SCOPED_TRACE(what);
        const int tested = count(frame, top, is), reference = count(frame, bottom, is);
        EXPECT_GT(reference, 100);
        EXPECT_NEAR(double(tested) / reference, 1.0, 0.2) << tested << " against " << reference;
    }
}

// MultiUVTest: the emissive texture reads TEXCOORD_1, which spans the glTF logo (green) in its
// corner; TEXCOORD_0 would show white "Multiple UVs not supported in this viewer" text. Under
// a black environment the frame shows the emission alone.
TEST(KhronosRender, MultiUvTestEmissionUsesTheSecondUvSet)
{
    LUMAR_RENDERER_OR_SKIP(renderer, kSize, kSize);
    GltfModel model = loadGltfModel(sample("MultiUVTest/MultiUVTest.glb"));
    const Scene dark{.environment = 0.0f, .background = {0, 0, 0}};
    const auto shares = [&](const GltfModel& m, const std::string& name) {
        renderer.removeModels();
        const ModelId id = renderer.addModel(m);
        const Frame frame = renderModel(renderer, id, m, View{{-1, -1, -1}, {0, 1, 0}, 0.8}, name, dark);
        int lit = 0, green = 0, white = 0;
        for (int y = 0; y < kSize; ++y)
            for (int x = 0; x < kSize; ++x) {
                const glm::ivec3 c = frame.at(x, y);
                if (std::max({c.r, c.g, c.b}) < 60)
                    continue;
                ++lit;
                green += c.g > c.r + 20 && c.g > 2 * c.b;
                white += std::min({c.r, c.g, c.b}) > 150;
            }
        return std::array<int, 3>{lit, green, white};
    };
    const auto [lit, green, white] = shares(model, "MultiUVTest");
    EXPECT_GT(lit, 1500) << "the logo glows on the three faces in view";
    EXPECT_GT(green, lit * 9 / 10);
    EXPECT_LT(white, lit / 50);
    // The control: the first uv set shows the text, so the measure tells the two apart.
    model.materials[0].uvTransforms[size_t(GltfTextureSlot::Emissive)].texCoord = 0;
    const auto [litText, greenText, whiteText] = shares(model, "MultiUVTest_texcoord0");
    EXPECT_GT(whiteText, litText / 4);
}

// TextureTransformTest (README): the top row's offsets show the U, V and UV checks (green, blue,
// cyan; yellow where the offset is lost); in the bottom row the arrow, rotated, scaled or
// both, points at the green "correct" marker, not at the yellow "not supported" or red "error"
// marker (their centres are the file's node translations).
TEST(KhronosRender, TextureTransformTestOffsetsAndArrowsAsStated)
{
    LUMAR_RENDERER_OR_SKIP(renderer, 512, 512);
    const GltfModel model = loadGltfModel(sample("TextureTransformTest/TextureTransformTest.gltf"));
    const ModelId id = renderer.addModel(model);
    const Frame frame = renderModel(renderer, id, model, View{}, "TextureTransformTest", {.size = 512, .focal = 600.0});
    const std::array<std::pair<const char*, bool (*)(const glm::ivec3&)>, 3> offsets{
        {{"Offset U", isGreen}, {"Offset V", isBlue}, {"Offset UV", [](const glm::ivec3& c) {
                                                           return isSecondary(c) && c.r < c.g && c.r < c.b;
                                                       }}}};
    for (const auto& [material, is] : offsets) {
        SCOPED_TRACE(material);
        const Rect r = projectedRect(frame, verticesOf(model, material), 0.05);
        const int pixels = (r.x1 - r.x0) * (r.y1 - r.y0);
        ASSERT_GT(pixels, 2000);
        EXPECT_GT(count(frame, r, is), pixels / 2);
        EXPECT_LT(count(frame, r, isYellow), 10);
    }
    struct Arrow {
        const char* material;
        glm::dvec3 correct, other; // marker centres: where it should point, where a failure points
    };
    const Arrow arrows[] = {
        {"Rotation", {-1.1 - 0.0790, -0.55 - 0.5163, 0.01}, {-1.1 + 0.2778, -0.55 - 0.2778, 0.01}},
        {"Rotation", {-1.1 - 0.0790, -0.55 - 0.5163, 0.01}, {-1.1 + 0.5163, -0.55 + 0.0790, 0.01}},
        {"Scale", {0.0185, -0.55 - 0.0185, 0.01}, {0.2778, -0.55 - 0.2778, 0.01}},
        {"All", {1.1 - 0.07, -0.55 - 0.25, 0.01}, {1.1 + 0.2778, -0.55 - 0.2778, 0.01}},
    };
    for (const Arrow& a : arrows) {
        SCOPED_TRACE(a.material);
        // The arrow's dark pixels; the one nearest each marker.
        const Rect r = projectedRect(frame, verticesOf(model, a.material), 0.0);
        const glm::dvec2 correct = frame.pixelOf(a.correct), other = frame.pixelOf(a.other);
        double toCorrect = 1e9, toOther = 1e9;
        int dark = 0;
        for (int y = r.y0; y < r.y1; ++y)
            for (int x = r.x0; x < r.x1; ++x) {
                const glm::ivec3 c = frame.at(x, y);
                if (std::max({c.r, c.g, c.b}) > 50)
                    continue;
                ++dark;
                toCorrect = std::min(toCorrect, glm::length(glm::dvec2(x, y) - correct));
                toOther = std::min(toOther, glm::length(glm::dvec2(x, y) - other));
            }
        EXPECT_GT(dark, 200) << "the arrow is drawn";
        // The markers are 0.1-0.15 model units wide; the tip stops short of the right one
        // (0.13 units away in the rotation quad) and twice as far from the others.
        EXPECT_LT(toCorrect, 0.2 * 600.0 / frame.cameraFromModel[3].z);
        EXPECT_LT(toCorrect * 2.0, toOther);
    }
}

// The white silhouette's extent, pixel edges (a glowing shape over a black camera image).
struct Extent {
    double left = 1e9, right = -1e9, top = 1e9, bottom = -1e9;
};

Extent silhouette(const Frame& frame)
{
    Extent e;
    for (int y = 0; y < frame.rgb.height; ++y)
        for (int x = 0; x < frame.rgb.width; ++x)
            if (frame.at(x, y).g > 128) {
                e.left = std::min(e.left, double(x));
                e.right = std::max(e.right, double(x + 1));
                e.top = std::min(e.top, double(y));
                e.bottom = std::max(e.bottom, double(y + 1));
            }
    return e;
}

// Where model-space points project, as pixel edges.
Extent projected(const Frame& frame, const std::vector<glm::dvec3>& points)
{
    Extent e;
    for (const glm::dvec3& p : points) {
        const glm::dvec2 q = frame.pixelOf(p) + glm::dvec2(0.5);
        e.left = std::min(e.left, q.x);
        e.right = std::max(e.right, q.x);
        e.top = std::min(e.top, q.y);
        e.bottom = std::max(e.bottom, q.y);
    }
    return e;
}

void expectExtent(const Extent& actual, const Extent& expected)
{
    // Rasterisation covers a pixel whose centre is inside: every edge within a pixel.
    EXPECT_NEAR(actual.left, expected.left, 1.0);
    EXPECT_NEAR(actual.right, expected.right, 1.0);
    EXPECT_NEAR(actual.top, expected.top, 1.0);
    EXPECT_NEAR(actual.bottom, expected.bottom, 1.0);
}

// `model`'s every primitive drawn glowing white on both sides (shape alone, no shading).
void makeGlowing(GltfModel& model)
{
    model.materials.assign(1, test::emissiveMaterial(glm::vec3(1.0f)));
    model.materials[0].doubleSided = true;
    for (GltfPrimitive& p : model.primitives)
        p.material = 0;
}

Frame renderPosed(SceneRenderer& renderer, ModelId id, const GltfModel& model, double seconds, const std::string& name)
{
    const ClipTime clip[] = {{0, seconds}};
    renderer.poseModel(id, clip);
    // Framed on the rest pose, so every time is seen from the same camera.
    return renderModel(renderer, id, model, View{{0, 0, -1}, {0, 1, 0}, 0.35}, name,
                       {.environment = 0.0f, .background = {0, 0, 0}});
}

// SimpleMorph: the triangle (0, 0), (1, 0), (0.5, 0.5) whose top vertex the two targets move by
// (-1, 1) and (1, 1); the animation's weights are (0, 0), (0, 1), (1, 1), (1, 0), (0, 0) at
// 0..4 s, linear between.
TEST(KhronosRender, SimpleMorphTopVertexFollowsTheAnimatedWeights)
{
    LUMAR_RENDERER_OR_SKIP(renderer, kSize, kSize);
    GltfModel model = loadGltfModel(sample("SimpleMorph/SimpleMorph.gltf"));
    makeGlowing(model);
    const ModelId id = renderer.addModel(model);
    const auto top = [](double w1, double w2) { return glm::dvec3(0.5 - w1 + w2, 0.5 + w1 + w2, 0.0); };
    const std::array<std::tuple<double, double, double>, 5> times{
        {{0.0, 0.0, 0.0}, {1.0, 0.0, 1.0}, {2.0, 1.0, 1.0}, {2.5, 1.0, 0.5}, {3.0, 1.0, 0.0}}};
    for (const auto& [seconds, w1, w2] : times) {
        SCOPED_TRACE(seconds);
        const Frame frame = renderPosed(renderer, id, model, seconds, "SimpleMorph_" + std::to_string(seconds));
        // The apex is sharp: its last pixels cover no pixel centre, up to 2.5 pixels at 2 s
        // (the triangle 2.5 high on a base of 1, a pixel wide 2.5 pixels below its tip).
        const Extent actual = silhouette(frame), expected = projected(frame, {{0, 0, 0}, {1, 0, 0}, top(w1, w2)});
        expectExtent({actual.left, actual.right, expected.top, actual.bottom}, expected);
        EXPECT_GE(actual.top, expected.top - 1.0);
        EXPECT_LE(actual.top, expected.top + 3.5);
    }
}

// SimpleSkin: a strip from y = 0 to 2 whose upper joint (node 2, at y = 1) the animation turns
// about z, 90 degrees at 1 s; each vertex follows its joints by its weights (rows at y = 0,
// 0.5, 1, 1.5, 2 weigh the upper joint 0, 0.25, 0.5, 0.75, 1).
TEST(KhronosRender, SimpleSkinBendsAsItsJointTurns)
{
    LUMAR_RENDERER_OR_SKIP(renderer, kSize, kSize);
    GltfModel model = loadGltfModel(sample("SimpleSkin/SimpleSkin.gltf"));
    makeGlowing(model);
    const ModelId id = renderer.addModel(model);
    const auto posed = [](double degrees) {
        const double a = glm::radians(degrees);
        std::vector<glm::dvec3> corners;
        for (int row = 0; row <= 4; ++row)
            for (const double x : {-0.5, 0.5}) {
                const glm::dvec2 rest(x, 0.5 * row);
                const glm::dvec2 r = rest - glm::dvec2(0, 1);
                const glm::dvec2 turned = glm::dvec2(0, 1) + glm::dvec2(std::cos(a) * r.x - std::sin(a) * r.y,
                                                                        std::sin(a) * r.x + std::cos(a) * r.y);
                const double w = 0.25 * row;
                corners.emplace_back(glm::dvec3((1 - w) * rest + w * turned, 0.0));
            }
        return corners;
    };
    // Rest, then 90 degrees at 1 s, and 45 at 0.5 s (the keyframe there).
    for (const auto& [seconds, degrees] : {std::pair{0.0, 0.0}, {1.0, 90.0}, {0.5, 45.0}, {4.0, -90.0}}) {
        SCOPED_TRACE(seconds);
        const Frame frame = renderPosed(renderer, id, model, seconds, "SimpleSkin_" + std::to_string(seconds));
        expectExtent(silhouette(frame), projected(frame, posed(degrees)));
    }
    // At 1 s the top (the upper joint's vertices) lies left of the strip, at x = -1.
    const Frame bent = renderPosed(renderer, id, model, 1.0, "SimpleSkin_bent");
    const glm::dvec2 leftOfKnee = bent.pixelOf({-0.9, 1.0, 0.0}), restTop = bent.pixelOf({0.3, 1.9, 0.0});
    EXPECT_GT(bent.at(int(leftOfKnee.x), int(leftOfKnee.y)).g, 128);
    EXPECT_LT(bent.at(int(restTop.x), int(restTop.y)).g, 20);
}

// A skinned model drawn without ever being posed (a still load, or before the first frame
// poses it) shows the rest pose its load skinned: SimpleSkin's straight strip, 1 x 2.
TEST(KhronosRender, SimpleSkinNeverPosedDrawsItsRestPose)
{
    LUMAR_RENDERER_OR_SKIP(renderer, kSize, kSize);
    GltfModel model = loadGltfModel(sample("SimpleSkin/SimpleSkin.gltf"));
    makeGlowing(model);
    std::vector<glm::dvec3> rest;
    for (int row = 0; row <= 4; ++row)
        for (const double x : {-0.5, 0.5})
            rest.emplace_back(x, 0.5 * row, 0.0);
    const Scene dark{.environment = 0.0f, .background = {0, 0, 0}};
    const View view{{0, 0, -1}, {0, 1, 0}, 0.35};
    const Frame animated = renderModel(renderer, renderer.addModel(model), model, view, "SimpleSkin_unposed", dark);
    expectExtent(silhouette(animated), projected(animated, rest));
    // The same model as a still one (its rig dropped: nothing could pose it).
    model.rig.reset();
    renderer.removeModels();
    const Frame still = renderModel(renderer, renderer.addModel(model), model, view, "SimpleSkin_still", dark);
    expectExtent(silhouette(still), projected(still, rest));
}

// Not a check: with LUMAR_KHRONOS_SWEEP=DIR, every .glb and .gltf in DIR is loaded and drawn
// from the front (with LUMAR_KHRONOS_DUMP, its frame kept), one line each: what loaded, or
// the one-line message lumar gives. docs/gltf-support.md's table was made this way.
TEST(KhronosRender, SweepDirectory)
{
    const char* dir = std::getenv("LUMAR_KHRONOS_SWEEP");
    if (dir == nullptr)
        GTEST_SKIP() << "LUMAR_KHRONOS_SWEEP=DIR not set";
    LUMAR_RENDERER_OR_SKIP(renderer, kSize, kSize);
    std::vector<std::filesystem::path> files;
    for (const auto& entry : std::filesystem::directory_iterator(dir))
        if (entry.path().extension() == ".glb" || entry.path().extension() == ".gltf")
            files.push_back(entry.path());
    std::sort(files.begin(), files.end());
    for (const std::filesystem::path& file : files) {
        std::string line = file.stem().string() + " | ";
        try {
            const GltfModel model = loadGltfModel(file);
            renderer.removeModels();
            const ModelId id = renderer.addModel(model);
            const double radius = 0.5 * glm::length(glm::dvec3(model.boundsMax) - glm::dvec3(model.boundsMin));
            renderModel(renderer, id, model, View{}, file.stem().string(),
                        {.modelScale = radius > 0.0 ? 1.0 / radius : 1.0});
            line += "loaded: " + std::to_string(model.primitives.size()) + " primitives, " +
                    std::to_string(model.triangleCount()) + " triangles" + (model.rig ? ", animated" : "");
        } catch (const std::exception& e) {
            line += std::string("refused: ") + e.what();
        }
        std::printf("SWEEP %s\n", line.c_str());
    }
}

} // namespace
} // namespace lumar
