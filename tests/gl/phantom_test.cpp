// Phantoms in the frame (DESIGN.md §6.5): a proxy of a real object writes depth only, so the
// camera image shows through it bit-exactly and a virtual object behind it is hidden, while
// the part of the object beside it is drawn.
#include <cstdlib>

#include <gtest/gtest.h>

#include "gl_test_support.h"
#include "gles_renderer/assets/builtin_shapes.h"

namespace lumar {
namespace {

constexpr int kWidth = 160, kHeight = 120;

// A busy camera image (any change shows), a white emissive quad 1 m ahead covering the
// frame's left and right halves, and a phantom box 0.5 m ahead in front of its left half
// only: the frame `renderer` makes of them. Behind the box (its projection: x in about
// [-0.25, -0.05] / 0.4 * 150 + 79.5 = [-14, 61]) the count of channel values that differ from
// the camera image by more than `tolerance`, and beside it the quad's pixel.
struct PhantomBeforeQuad {
    size_t changedBehindBox = 0;
    glm::ivec3 quad{0};
};

PhantomBeforeQuad renderPhantomBeforeQuad(SceneRenderer& renderer, int tolerance)
{
    const CameraIntrinsics k = test::makeIntrinsics(kWidth, kHeight, 150, 150, 79.5, 59.5);
    Image8 camera(kWidth, kHeight, 3);
    for (size_t i = 0; i < camera.data.size(); ++i)
        camera.data[i] = uint8_t((i * 37) % 251);
    const ModelId quad =
        renderer.addModel(test::cameraFacingRectangle(-0.4f, -0.2f, 0.4f, 0.2f, test::emissiveMaterial({1, 1, 1})));
    const ModelId box = renderer.addModel(makeCube());
    const DrawItem items[] = {{quad, test::translation(0, 0, 1)},
                              {box, test::translation(-0.15, 0, 0.5) * glm::dmat4(glm::dmat3(0.2)), -1, true}};
    renderer.render(camera, k, items);
    Image8 out;
    renderer.readback(out);
    PhantomBeforeQuad result;
    for (int y = 40; y < 80; ++y)
        for (int x = 10; x < 50; ++x)
            for (int c = 0; c < 3; ++c)
                result.changedBehindBox += std::abs(int(out.at(x, y)[c]) - int(camera.at(x, y)[c])) > tolerance;
    const uint8_t* beside = out.at(120, 60);
    result.quad = glm::ivec3(beside[0], beside[1], beside[2]);
    return result;
}

TEST(Phantom, HidesVirtualObjectsBehindItAndLeavesTheCameraImage)
{
    LUMAR_RENDERER_OR_SKIP(renderer, kWidth, kHeight);
    const PhantomBeforeQuad frame = renderPhantomBeforeQuad(renderer, 0);
    // Behind the phantom: the camera image, unchanged.
    EXPECT_EQ(frame.changedBehindBox, 0u);
    // Beside it the quad is drawn (white emission, tone-mapped).
    EXPECT_TRUE(glm::all(glm::greaterThan(frame.quad, glm::ivec3(150)))) << frame.quad.x;
}

// With shadows on the phantoms' depth is drawn by ShadowPass::drawReceivers, only where a later
// pass reads it: the darkening's rectangles and the virtual objects' window boxes. Here the
// light comes from the left and from beyond the quad, so neither seen face of the box (its
// front and its right side) faces it, and the box lies far beyond the flat quad's contact
// reach: nothing darkens the box, and its depth must still hide the quad behind it.
TEST(Phantom, HidesVirtualObjectsBehindItWhereNothingDarkensItWithShadowsOn)
{
    RenderOptions options;
    options.shadows.enabled = true;
    options.shadows.mapSize = 512;
    LUMAR_RENDERER_OR_SKIP(renderer, kWidth, kHeight, options);
    renderer.setEnvironment(test::uniformEnvironment(1.0f), 1.0f);
    renderer.setEnvironmentRotation(glm::dmat3(1.0)); // the environment frame is the camera's
    DirectionalLight light;
    light.direction = glm::normalize(glm::dvec3(-1.0, 0.0, 0.3));
    light.intensity = 2.0f;
    renderer.setLight(light);
    const PhantomBeforeQuad frame = renderPhantomBeforeQuad(renderer, 1);
    EXPECT_EQ(frame.changedBehindBox, 0u);
    EXPECT_TRUE(glm::all(glm::greaterThan(frame.quad, glm::ivec3(150)))) << frame.quad.x;
}

} // namespace
} // namespace lumar
