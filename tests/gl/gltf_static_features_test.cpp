// Issue 20's static-model features as the renderer draws them, from small glTF files built
// here (tests/unit/render/feature_gltf.h): sampler wrap modes, vertex colours, the second uv
// set, a texture transform, occlusion with its strength, quantized positions, unlit colour,
// MASK cut-outs, BLEND mixing in back-to-front order, and GPU instancing. Every check reads
// pixels of the rendered image: unlit materials make the expected colour exact.
#include <algorithm>
#include <array>
#include <cmath>
#include <optional>
#include <string>

#include <glm/gtc/matrix_transform.hpp>
#include <gtest/gtest.h>

#include "../unit/render/feature_gltf.h"
#include "gl_test_support.h"

namespace lumar {
namespace {

using test::FeatureGltf;
using test::ScratchDir;

constexpr int kWidth = 160, kHeight = 120;
constexpr double kFocal = 100.0, kDepth = 2.5; // 40 pixels per model unit at the model's plane
const std::array<uint8_t, 4> kRed{255, 0, 0, 255}, kGreen{0, 255, 0, 255}, kBlue{0, 0, 255, 255},
    kWhite{255, 255, 255, 255};
const glm::ivec3 kBackground{10, 20, 30};

int srgbCode(double linear)
{
    const double c = std::clamp(linear, 0.0, 1.0);
    return int(std::lround(255.0 * (c <= 0.0031308 ? 12.92 * c : 1.055 * std::pow(c, 1.0 / 2.4) - 0.055)));
}

double linearFromCode(int code)
{
    const double c = code / 255.0;
    return c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4);
}

struct Frame {
    Image8 rgb;
    // The pixel where model point (x, y, 0) appears: the model's +x right, +y up.
    [[nodiscard]] glm::ivec3 at(double x, double y) const
    {
        const int px = int(std::floor(kWidth / 2.0 + kFocal * x / kDepth));
        const int py = int(std::floor(kHeight / 2.0 - kFocal * y / kDepth));
        const uint8_t* p = rgb.data.data() + (size_t(py) * size_t(kWidth) + size_t(px)) * 3;
        return {p[0], p[1], p[2]};
    }
};

// Renders the model at kDepth facing the camera over a kBackground image, lit by a uniform
// environment of `environment`; empty when there is no GLES 3 renderer.
std::optional<Frame> render(const std::filesystem::path& file, float environment = 0.5f)
{
    const GltfModel model = loadGltfModel(file);
    test::RendererOrReason made = test::tryCreateRenderer(kWidth, kHeight);
    if (!made.renderer)
        return std::nullopt;
    SceneRenderer& renderer = *made.renderer;
    renderer.setEnvironment(test::uniformEnvironment(environment), 1.0f);
    const ModelId id = renderer.addModel(model);
    // Model +z towards the camera, +y up.
    const glm::dmat4 cameraFromModel =
        glm::rotate(test::translation(0, 0, kDepth), glm::radians(180.0), glm::dvec3(1, 0, 0));
    const DrawItem item{id, cameraFromModel};
    renderer.render(
        test::solidImage(kWidth, kHeight, uint8_t(kBackground.r), uint8_t(kBackground.g), uint8_t(kBackground.b)),
        test::makeIntrinsics(kWidth, kHeight, kFocal, kFocal, kWidth / 2.0, kHeight / 2.0), {&item, 1});
    Frame frame;
    renderer.readback(frame.rgb);
    return frame;
}

#define RENDER_OR_SKIP(frame, ...)                                                                                     \
    const std::optional<Frame> frame##Optional = render(__VA_ARGS__);                                                  \
    if (!frame##Optional)                                                                                              \
        GTEST_SKIP() << "no GLES 3 renderer";                                                                          \
    const Frame& frame = *frame##Optional

void expectColour(const glm::ivec3& actual, const glm::ivec3& expected, int tolerance, const std::string& what)
{
    for (int c = 0; c < 3; ++c)
        EXPECT_NEAR(actual[c], expected[c], tolerance)
            << what << ": got (" << actual.r << ", " << actual.g << ", " << actual.b << "), expected (" << expected.r
            << ", " << expected.g << ", " << expected.b << ")";
}

std::string unlitTextured(int texture, const std::string& textureInfoMore = {}, const std::string& more = {})
{
    return R"({"pbrMetallicRoughness":{"baseColorTexture":{"index":)" + std::to_string(texture) + textureInfoMore +
           R"(}},"extensions":{"KHR_materials_unlit":{}})" + more + "}";
}

constexpr const char* kNearest = R"("magFilter":9728,"minFilter":9728)";

TEST(GltfStaticRender, WrapModesRepeatMirrorAndClamp)
{
    ScratchDir dir;
    FeatureGltf g;
    g.extensionsUsed = {"KHR_materials_unlit"};
    const Image8 quadrants = test::texelImage(2, 2, {kRed, kGreen, kBlue, kWhite});
    const std::array<int, 3> modes{10497, 33648, 33071};
    const std::array<double, 3> left{-1.95, -0.6, 0.75};
    constexpr double kSide = 1.2;
    for (size_t i = 0; i < 3; ++i) {
        const std::string mode = std::to_string(modes[i]);
        const int texture =
            g.texture(dir, "q" + mode, quadrants, R"({"wrapS":)" + mode + R"(,"wrapT":)" + mode + "," + kNearest + "}");
        // uv (0, 0) at the top-left corner, (2, 2) at the bottom-right: two tiles each way.
        g.primitive(g.quadAttributes(float(left[i]), -0.6f, float(left[i] + kSide), 0.6f, 0, 0, 0, 2, 2),
                    g.material(unlitTextured(texture)));
    }
    RENDER_OR_SKIP(frame, g.save(dir, "wrap"));
    const auto at = [&](size_t quad, double u, double v) {
        return frame.at(left[quad] + u / 2.0 * kSide, 0.6 - v / 2.0 * kSide);
    };
    const glm::ivec3 red{255, 0, 0}, green{0, 255, 0}, blue{0, 0, 255};
    // The first tile is the texture itself in every mode.
    for (size_t q = 0; q < 3; ++q) {
        expectColour(at(q, 0.25, 0.25), red, 1, "first tile, top left");
        expectColour(at(q, 0.75, 0.25), green, 1, "first tile, top right");
    }
    // Second tile along u: repeat starts again, mirror runs backwards, clamp keeps the edge.
    expectColour(at(0, 1.25, 0.25), red, 1, "repeat s");
    expectColour(at(0, 1.75, 0.25), green, 1, "repeat s");
    expectColour(at(1, 1.25, 0.25), green, 1, "mirror s");
    expectColour(at(1, 1.75, 0.25), red, 1, "mirror s");
    expectColour(at(2, 1.25, 0.25), green, 1, "clamp s");
    expectColour(at(2, 1.75, 0.25), green, 1, "clamp s");
    // And along v.
    expectColour(at(0, 0.25, 1.25), red, 1, "repeat t");
    expectColour(at(0, 0.25, 1.75), blue, 1, "repeat t");
    expectColour(at(1, 0.25, 1.25), blue, 1, "mirror t");
    expectColour(at(1, 0.25, 1.75), red, 1, "mirror t");
    expectColour(at(2, 0.25, 1.25), blue, 1, "clamp t");
    expectColour(at(2, 0.25, 1.75), blue, 1, "clamp t");
}

TEST(GltfStaticRender, VertexColoursMultiplyTheBaseColour)
{
    ScratchDir dir;
    FeatureGltf g;
    g.extensionsUsed = {"KHR_materials_unlit"};
    const int rgb =
        g.accessor<float>({0.2f, 0.5f, 0.8f, 0.2f, 0.5f, 0.8f, 0.2f, 0.5f, 0.8f, 0.2f, 0.5f, 0.8f}, 5126, "VEC3", 4);
    const int rgba = g.accessor<uint8_t>({51, 255, 0, 255, 51, 255, 0, 255, 51, 255, 0, 255, 51, 255, 0, 255}, 5121,
                                         "VEC4", 4, true);
    const int unlit = g.material(R"({"pbrMetallicRoughness":{"baseColorFactor":[0.5,1,1,1]},)"
                                 R"("extensions":{"KHR_materials_unlit":{}}})");
    g.primitive(g.quadAttributes(-1.5f, -1, -0.1f, 1, 0, 0, 0, 1, 1) + R"(,"COLOR_0":)" + std::to_string(rgb), unlit);
    g.primitive(g.quadAttributes(0.1f, -1, 1.5f, 1, 0, 0, 0, 1, 1) + R"(,"COLOR_0":)" + std::to_string(rgba), unlit);
    RENDER_OR_SKIP(frame, g.save(dir, "colours"));
    expectColour(frame.at(-0.8, 0), {srgbCode(0.1), srgbCode(0.5), srgbCode(0.8)}, 1, "float rgb x base colour");
    expectColour(frame.at(0.8, 0), {srgbCode(0.1), srgbCode(1.0), 0}, 1, "normalized ubyte rgba x base colour");
}

TEST(GltfStaticRender, SecondUvSetAndTextureTransform)
{
    ScratchDir dir;
    FeatureGltf g;
    g.extensionsUsed = {"KHR_materials_unlit", "KHR_texture_transform"};
    const int halves =
        g.texture(dir, "halves", test::texelImage(2, 1, {kRed, kGreen}), std::string("{") + kNearest + "}");
    // Left quad: TEXCOORD_0 is (0, 0) everywhere; the texture reads TEXCOORD_1, which spans it.
    const int uv1 = g.accessor<float>({0, 0, 1, 0, 1, 1, 0, 1}, 5126, "VEC2", 4);
    g.primitive(g.quadAttributes(-1.8f, -1, -0.2f, 1, 0, 0, 0, 0, 0) + R"(,"TEXCOORD_1":)" + std::to_string(uv1),
                g.material(unlitTextured(halves, R"(,"texCoord":1)")));
    // Right quad: offset by half the texture (REPEAT): green on the left, red on the right.
    g.primitive(g.quadAttributes(0.2f, -1, 1.8f, 1, 0, 0, 0, 1, 1),
                g.material(unlitTextured(halves, R"(,"extensions":{"KHR_texture_transform":{"offset":[0.5,0]}})")));
    RENDER_OR_SKIP(frame, g.save(dir, "uvsets"));
    expectColour(frame.at(-1.4, 0), {255, 0, 0}, 1, "TEXCOORD_1, left half");
    expectColour(frame.at(-0.6, 0), {0, 255, 0}, 1, "TEXCOORD_1, right half");
    expectColour(frame.at(0.6, 0), {0, 255, 0}, 1, "offset, left half");
    expectColour(frame.at(1.4, 0), {255, 0, 0}, 1, "offset, right half");
}

TEST(GltfStaticRender, OcclusionDarkensTheEnvironmentLightByItsStrength)
{
    ScratchDir dir;
    FeatureGltf g;
    // Red channel 0 on the left (fully occluded), 255 on the right; strength 0.5 leaves half
    // the light on the left. The right half is lit as without occlusion.
    const int occlusion = g.texture(dir, "ao", test::texelImage(2, 1, {{0, 0, 0, 255}, {255, 255, 255, 255}}),
                                    std::string("{") + kNearest + "}");
    const std::string lit = R"({"pbrMetallicRoughness":{"baseColorFactor":[0.5,0.5,0.5,1],"metallicFactor":0,)"
                            R"("roughnessFactor":1})";
    g.primitive(
        g.quadAttributes(-1.8f, -1, -0.2f, 1, 0, 0, 0, 1, 1),
        g.material(lit + R"(,"occlusionTexture":{"index":)" + std::to_string(occlusion) + R"(,"strength":0.5}})"));
    g.primitive(g.quadAttributes(0.2f, -1, 1.8f, 1, 0, 0, 0, 1, 1), g.material(lit + "}"));
    RENDER_OR_SKIP(frame, g.save(dir, "occlusion"));
    const glm::ivec3 occluded = frame.at(-1.4, 0), open = frame.at(-0.6, 0), plain = frame.at(1.0, 0);
    expectColour(open, plain, 1, "occlusion 1 changes nothing");
    ASSERT_GT(open.g, 60) << "lit well enough to measure";
    const double ratio = linearFromCode(occluded.g) / linearFromCode(open.g);
    EXPECT_NEAR(ratio, 0.5, 0.03) << "1 + 0.5 (0 - 1) of the light";
}

TEST(GltfStaticRender, QuantizedPositionsAndUnlitColourExactly)
{
    ScratchDir dir;
    FeatureGltf g;
    g.extensionsUsed = {"KHR_mesh_quantization", "KHR_materials_unlit"};
    g.extensionsRequired = g.extensionsUsed;
    // A quad from (-1, -1) to (1, 1) as normalized shorts, scaled by the node.
    const int position = g.accessor<int16_t>({-32767, 32767, 0, 32767, 32767, 0, 32767, -32767, 0, -32767, -32767, 0},
                                             5122, "VEC3", 4, true);
    const int uv = g.accessor<uint8_t>({0, 0, 255, 0, 255, 255, 0, 255}, 5121, "VEC2", 4, true);
    g.primitive(R"("POSITION":)" + std::to_string(position) + R"(,"TEXCOORD_0":)" + std::to_string(uv),
                g.material(R"({"pbrMetallicRoughness":{"baseColorFactor":[0.2,0.5,0.8,1]},)"
                           R"("extensions":{"KHR_materials_unlit":{}}})"));
    g.node = R"({"mesh":0,"scale":[0.5,0.5,0.5]})";
    const auto file = g.save(dir, "quantized");
    const glm::ivec3 expected{srgbCode(0.2), srgbCode(0.5), srgbCode(0.8)};
    for (const float environment : {0.1f, 3.0f}) {
        RENDER_OR_SKIP(frame, file, environment);
        expectColour(frame.at(0, 0), expected, 1, "unlit: the base colour whatever the light");
        expectColour(frame.at(0.4, 0.4), expected, 1, "inside the quad");
        expectColour(frame.at(0.6, 0.6), kBackground, 0, "outside the quad (half size)");
    }
}

TEST(GltfStaticRender, MaskCutsOut)
{
    ScratchDir dir;
    FeatureGltf g;
    g.extensionsUsed = {"KHR_materials_unlit"};
    const int texture = g.texture(dir, "cut", test::texelImage(2, 1, {{255, 0, 0, 40}, {0, 255, 0, 200}}),
                                  std::string("{") + kNearest + "}");
    g.primitive(g.quadAttributes(-1.5f, -1, 1.5f, 1, 0, 0, 0, 1, 1),
                g.material(unlitTextured(texture, "", R"(,"alphaMode":"MASK","alphaCutoff":0.5)")));
    RENDER_OR_SKIP(frame, g.save(dir, "mask"));
    expectColour(frame.at(-0.75, 0), kBackground, 0, "alpha 40/255 is cut out");
    expectColour(frame.at(0.75, 0), {0, 255, 0}, 1, "alpha 200/255 stays, opaque");
}

TEST(GltfStaticRender, BlendMixesBackToFront)
{
    ScratchDir dir;
    FeatureGltf g;
    g.extensionsUsed = {"KHR_materials_unlit"};
    const auto unlit = [&](const char* colour, const char* mode) {
        return g.material(std::string(R"({"pbrMetallicRoughness":{"baseColorFactor":)") + colour +
                          R"(},"extensions":{"KHR_materials_unlit":{}},"alphaMode":")" + mode + "\"}");
    };
    // In the file nearest first, so drawing in file order (or with depth writes) goes wrong:
    // red half-transparent nearest, green half-transparent behind it, opaque blue at the back.
    g.primitive(g.quadAttributes(-1.5f, -1, 0.5f, 1, 0.5f, 0, 0, 1, 1), unlit("[1,0,0,0.5]", "BLEND"));
    g.primitive(g.quadAttributes(-0.5f, -1, 1.5f, 1, 0.25f, 0, 0, 1, 1), unlit("[0,1,0,0.5]", "BLEND"));
    g.primitive(g.quadAttributes(-1, -0.5f, 1, 0.5f, -0.5f, 0, 0, 1, 1), unlit("[0,0,1,1]", "OPAQUE"));
    RENDER_OR_SKIP(frame, g.save(dir, "blend"));
    // Codes blend as stored (the frame is sRGB-encoded 8 bits): 0.5 each.
    expectColour(frame.at(0, 0), {128, 64, 64}, 2, "red over green over blue");
    expectColour(frame.at(-1.0, 0.8), {133, 10, 15}, 2, "red over the camera image");
    expectColour(frame.at(1.0, 0.8), {5, 138, 15}, 2, "green over the camera image");
    expectColour(frame.at(-0.8, 0), {128, 0, 128}, 2, "red over blue");
}

TEST(GltfStaticRender, GpuInstancesAreAllDrawn)
{
    ScratchDir dir;
    FeatureGltf g;
    g.extensionsUsed = {"KHR_materials_unlit", "EXT_mesh_gpu_instancing"};
    g.primitive(g.quadAttributes(-0.3f, -0.3f, 0.3f, 0.3f, 0, 0, 0, 1, 1),
                g.material(R"({"pbrMetallicRoughness":{"baseColorFactor":[0,1,0,1]},)"
                           R"("extensions":{"KHR_materials_unlit":{}}})"));
    const int translation = g.accessor<float>({-1.2f, 0, 0, 0, 0.6f, 0, 1.2f, 0, 0}, 5126, "VEC3", 3);
    g.node = R"({"mesh":0,"extensions":{"EXT_mesh_gpu_instancing":{"attributes":{"TRANSLATION":)" +
             std::to_string(translation) + "}}}}";
    RENDER_OR_SKIP(frame, g.save(dir, "instances"));
    expectColour(frame.at(-1.2, 0), {0, 255, 0}, 1, "instance 0");
    expectColour(frame.at(0, 0.6), {0, 255, 0}, 1, "instance 1");
    expectColour(frame.at(1.2, 0), {0, 255, 0}, 1, "instance 2");
    expectColour(frame.at(0, -0.6), kBackground, 0, "no instance there");
}

} // namespace
} // namespace lumar
