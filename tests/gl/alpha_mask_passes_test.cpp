// glTF alphaMode MASK beyond the frame (issue 17 deliverable 3, issue 20): a cut-out leaf
// casts a shadow with its hole in it (the shadow map's depth_only.frag cuts as mesh.frag
// does) and shows its hole in a neighbour's environment map. Each check against the same leaf
// drawn OPAQUE, measured from rendered pixels.
#include <cmath>
#include <numbers>

#include <gtest/gtest.h>

#include "gl_readback.h"
#include "gl_test_support.h"
#include "gles_renderer/assets/builtin_shapes.h"

namespace lumar {
namespace {

constexpr int kWidth = 200, kHeight = 150;
constexpr double kFocal = 250.0, kCx = 99.5, kCy = 74.5;
constexpr uint8_t kGrey = 128;

// A leaf: the quad c0..c3 (uv (0, 0) at c0, (1, 1) at c2) whose base colour texture is 2 x 2
// texels, nearest-sampled, the one at uv (0, 0) (next to c0) transparent: MASK cuts that
// quarter away at the default cutoff 0.5.
GltfModel leaf(const std::array<glm::vec3, 4>& corners, GltfAlphaMode mode, const glm::vec3& emission = {})
{
    GltfMaterial m = emission == glm::vec3(0.0f) ? GltfMaterial{} : test::emissiveMaterial(emission);
    m.baseColorTexture = 0;
    m.alphaMode = mode;
    m.doubleSided = true;
    GltfModel model = test::makeQuad(corners, m);
    Image8 image(2, 2, 4);
    std::fill(image.data.begin(), image.data.end(), uint8_t(255));
    image.at(0, 0)[3] = 0;
    model.textures.push_back({image, true});
    model.textureSamplers.push_back({33071, 33071, 9728, 9728});
    return model;
}

// Shadows: the camera 1 m above the ground looking down (world z up), the light at 45 degrees
// elevation along +x, the leaf level 0.3 m above a ground phantom.
glm::dmat4 cameraFromWorld()
{
    return test::cameraLookingDownFromOneMetre();
}

glm::dvec2 pixelOf(const glm::dvec3& p)
{
    const glm::dvec3 c(cameraFromWorld() * glm::dvec4(p, 1.0));
    return {kCx + kFocal * c.x / c.z, kCy + kFocal * c.y / c.z};
}

Image8 renderLeafShadow(GltfAlphaMode mode, const glm::dvec3& towardsLight)
{
    RenderOptions options;
    options.shadows.enabled = true;
    test::RendererOrReason made = test::tryCreateRenderer(kWidth, kHeight, options);
    if (!made.renderer)
        return {};
    SceneRenderer& renderer = *made.renderer;
    renderer.setEnvironment(test::uniformEnvironment(1.0f), 1.0f);
    // World (z up) to the environment frame (+Y up): (x, y, z) -> (x, z, -y).
    const glm::dmat3 environmentFromWorld(glm::dvec3(1, 0, 0), glm::dvec3(0, 0, -1), glm::dvec3(0, 1, 0));
    renderer.setEnvironmentRotation(environmentFromWorld * glm::dmat3(glm::inverse(cameraFromWorld())));
    DirectionalLight light;
    light.direction = environmentFromWorld * towardsLight;
    light.intensity = 2.0f;
    renderer.setLight(light);
    const ModelId cube = renderer.addModel(makeCube());
    const ModelId leafModel = renderer.addModel(leaf({glm::vec3(-0.1f, -0.1f, 0.3f), glm::vec3(0.1f, -0.1f, 0.3f),
                                                      glm::vec3(0.1f, 0.1f, 0.3f), glm::vec3(-0.1f, 0.1f, 0.3f)},
                                                     mode));
    glm::dmat4 ground(1.0);
    ground[0][0] = ground[1][1] = 1.2;
    ground[2][2] = 0.02;
    ground[3] = glm::dvec4(0.0, 0.0, -0.01, 1.0);
    const DrawItem items[] = {{cube, cameraFromWorld() * ground, -1, true}, {leafModel, cameraFromWorld(), -1}};
    renderer.render(test::solidImage(kWidth, kHeight, kGrey, kGrey, kGrey),
                    test::makeIntrinsics(kWidth, kHeight, kFocal, kFocal, kCx, kCy), items);
    Image8 out;
    renderer.readback(out);
    return out;
}

TEST(AlphaMask, CutOutLeafCastsALeafShapedShadow)
{
    const double elevation = std::numbers::pi / 4.0;
    const glm::dvec3 towardsLight(std::cos(elevation), 0.0, std::sin(elevation));
    const Image8 masked = renderLeafShadow(GltfAlphaMode::Mask, towardsLight);
    if (masked.data.empty())
        GTEST_SKIP() << "no GLES 3 renderer";
    const Image8 opaque = renderLeafShadow(GltfAlphaMode::Opaque, towardsLight);
    // Where each quarter's centre falls on the ground along the light (clear of the leaf
    // itself, which lies 0.3 m to the light's side of its shadow).
    const auto shadowCode = [&](const Image8& image, double x, double y) {
        const glm::dvec3 onLeaf(x, y, 0.3);
        const glm::dvec2 p = pixelOf(onLeaf - towardsLight * (onLeaf.z / towardsLight.z));
        return int(image.at(int(std::lround(p.x)), int(std::lround(p.y)))[1]);
    };
    // The cut quarter (next to c0 = (-0.1, -0.1)) lets the light through: the camera image.
    EXPECT_NEAR(shadowCode(masked, -0.05, -0.05), kGrey, 2);
    // The rest shadows the ground as the opaque leaf does.
    for (const auto& [x, y] : {std::pair{0.05, -0.05}, {0.05, 0.05}, {-0.05, 0.05}}) {
        EXPECT_LT(shadowCode(masked, x, y), kGrey - 25) << x << "," << y;
        EXPECT_NEAR(shadowCode(masked, x, y), shadowCode(opaque, x, y), 2) << x << "," << y;
    }
    EXPECT_LT(shadowCode(opaque, -0.05, -0.05), kGrey - 25) << "the opaque leaf shadows all of it";
}

// Environment maps: a red glowing leaf 0.16 m along +x of a small cube fills part of the
// cube's +X face; cut, its transparent quarter shows the environment behind it instead.
TEST(AlphaMask, CutOutLeafIsCutInTheEnvironmentMaps)
{
    std::array<int, 2> red{};
    for (const GltfAlphaMode mode : {GltfAlphaMode::Opaque, GltfAlphaMode::Mask}) {
        LUMAR_RENDERER_OR_SKIP(renderer, 160, 120);
        renderer.setEnvironment(test::uniformEnvironment(0.2f), 1.0f);
        const ModelId cube = renderer.addModel(makeCube());
        // Facing -x (towards the cube), spanning y and z by +-0.1 around (0.1, 0, 0.5).
        const ModelId leafModel = renderer.addModel(leaf({glm::vec3(0.1f, -0.1f, 0.4f), glm::vec3(0.1f, 0.1f, 0.4f),
                                                          glm::vec3(0.1f, 0.1f, 0.6f), glm::vec3(0.1f, -0.1f, 0.6f)},
                                                         mode, glm::vec3(3.0f, 0.0f, 0.0f)));
        glm::dmat4 small = test::translation(-0.06, 0.0, 0.5) * glm::dmat4(glm::dmat3(0.05));
        const DrawItem items[] = {{cube, small, 0}, {leafModel, glm::dmat4(1.0), 1}};
        renderer.render(test::solidImage(160, 120, 0, 0, 0), test::makeIntrinsics(160, 120, 200, 200, 79.5, 59.5),
                        items);
        ASSERT_NE(renderer.objectMaps(0), nullptr);
        const IblSettings settings;
        const CubeMapF sees = test::readMirrorMap(*renderer.objectMaps(0), settings.mirrorSize);
        const ImageF& face = sees.faces[0]; // +X (the environment frame is the camera's here)
        for (size_t i = 0; i < face.data.size(); i += 3)
            red[mode == GltfAlphaMode::Mask] += face.data[i] > 1.0f && face.data[i + 1] < 0.5f;
    }
    ASSERT_GT(red[0], 200) << "the leaf fills part of the face";
    // A quarter of the leaf cut: three quarters of its texels left (edges within a few %).
    EXPECT_NEAR(double(red[1]) / red[0], 0.75, 0.05) << red[1] << " of " << red[0];
}

} // namespace
} // namespace lumar
