// The shipped demo model end to end through the loader and the renderer at 1280x720: it
// appears inside the projection of its bounding box, and the frame time is reported
// (measured, never asserted: DESIGN.md section 9).
#include <chrono>
#include <cstdio>
#include <filesystem>

#include <glm/gtc/matrix_transform.hpp>
#include <gtest/gtest.h>

#include "gl_test_support.h"

namespace lumar {
namespace {

constexpr int kWidth = 1280, kHeight = 720;

TEST(MilkTruck, RendersInsideItsProjectedBoundsAndReportsFrameTime)
{
    const std::filesystem::path file =
        std::filesystem::path(LUMAR_SOURCE_DIR) / "daemon/assets/models/CesiumMilkTruck.glb";
    const GltfModel truck = loadGltfModel(file);
    LUMAR_RENDERER_OR_SKIP(renderer, kWidth, kHeight);
    renderer.setEnvironment(test::uniformEnvironment(0.8f), 1.0f);
    const ModelId id = renderer.addModel(truck);

    // The truck's centre 9 m ahead, turned three-quarters towards the camera; model +Y
    // (glTF up) becomes camera -y (up in the image).
    const glm::dvec3 centre = glm::dvec3(truck.boundsMin + truck.boundsMax) * 0.5;
    glm::dmat4 cameraFromModel = test::translation(0, 0, 9);
    cameraFromModel = glm::rotate(cameraFromModel, glm::radians(180.0), glm::dvec3(1, 0, 0));
    cameraFromModel = glm::rotate(cameraFromModel, glm::radians(35.0), glm::dvec3(0, 1, 0));
    cameraFromModel = glm::translate(cameraFromModel, -centre);
    const DrawItem item{id, cameraFromModel};

    const CameraIntrinsics k = defaultIntrinsics(kWidth, kHeight);
    const Image8 background = test::solidImage(kWidth, kHeight, 10, 20, 30);
    Image8 out;
    renderer.render(background, k, {&item, 1});
    renderer.readback(out);

    // Projected bounding box of the 8 corners of the model's bounds (+-1 px).
    glm::dvec2 lo(1e9), hi(-1e9);
    for (int corner = 0; corner < 8; ++corner) {
        const glm::dvec3 p((corner & 1) ? truck.boundsMax.x : truck.boundsMin.x,
                           (corner & 2) ? truck.boundsMax.y : truck.boundsMin.y,
                           (corner & 4) ? truck.boundsMax.z : truck.boundsMin.z);
        const glm::dvec2 uv = k.project(glm::dvec3(cameraFromModel * glm::dvec4(p, 1.0)));
        lo = glm::min(lo, uv);
        hi = glm::max(hi, uv);
    }
    size_t changed = 0, outside = 0;
    for (int y = 0; y < kHeight; ++y)
        for (int x = 0; x < kWidth; ++x) {
            const uint8_t* o = out.at(x, y);
            const uint8_t* b = background.at(x, y);
            if (o[0] == b[0] && o[1] == b[1] && o[2] == b[2])
                continue;
            ++changed;
            outside += x < lo.x - 1 || x > hi.x + 1 || y < lo.y - 1 || y > hi.y + 1;
        }
    const double boxArea = (hi.x - lo.x) * (hi.y - lo.y);
    EXPECT_EQ(outside, 0u);
    EXPECT_GT(double(changed), 0.3 * boxArea) << "the truck should fill a good part of its box";

    constexpr int frames = 20;
    const auto start = std::chrono::steady_clock::now();
    for (int i = 0; i < frames; ++i) {
        renderer.render(background, k, {&item, 1});
        renderer.readback(out);
    }
    const double ms =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count() / frames;
    RecordProperty("render_readback_ms_per_frame", std::to_string(ms));
    std::printf("CesiumMilkTruck %dx%d (%zu triangles): %.2f ms per frame, render + readback\n", kWidth, kHeight,
                truck.triangleCount(), ms);
}

} // namespace
} // namespace lumar
