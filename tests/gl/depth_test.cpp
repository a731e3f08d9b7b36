// Depth testing: the nearer surface wins whatever the draw order.
#include <gtest/gtest.h>

#include "gl_test_support.h"

namespace lumar {
namespace {

TEST(Depth, TheNearerOfTwoOverlappingQuadsWinsInEitherDrawOrder)
{
    constexpr int w = 160, h = 120;
    LUMAR_RENDERER_OR_SKIP(renderer, w, h);
    renderer.setEnvironment(test::uniformEnvironment(0.0f), 1.0f);
    const CameraIntrinsics k = test::makeIntrinsics(w, h, 120, 120, 79.5, 59.5);
    // Red 1 m ahead over the left half-ish, green 2 m ahead over the right half-ish; they
    // overlap around the image centre.
    const ModelId red =
        renderer.addModel(test::cameraFacingRectangle(-0.3f, -0.2f, 0.1f, 0.2f, test::emissiveMaterial({4, 0, 0})));
    const ModelId green =
        renderer.addModel(test::cameraFacingRectangle(-0.2f, -0.4f, 0.8f, 0.4f, test::emissiveMaterial({0, 4, 0})));
    const DrawItem nearRed{red, test::translation(0, 0, 1)};
    const DrawItem farGreen{green, test::translation(0, 0, 2)};
    const Image8 background = test::solidImage(w, h, 0, 0, 255);

    const DrawItem orders[2][2] = {{nearRed, farGreen}, {farGreen, nearRed}};
    for (const auto& order : orders) {
        Image8 out;
        renderer.render(background, k, order);
        renderer.readback(out);
        // Centre (79.5, 59.5) +- a few pixels lies in both: red must win.
        const uint8_t* overlap = out.at(80, 60);
        EXPECT_GT(overlap[0], 200);
        EXPECT_EQ(overlap[1], 0);
        // Red spans u in [43.5, 91.5], green [67.5, 127.5]: x = 110 is green only.
        const uint8_t* greenOnly = out.at(110, 60);
        EXPECT_EQ(greenOnly[0], 0);
        EXPECT_GT(greenOnly[1], 200);
        // Outside both: the camera image.
        const uint8_t* neither = out.at(2, 2);
        EXPECT_EQ(neither[2], 255);
    }
}

} // namespace
} // namespace lumar
