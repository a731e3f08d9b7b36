// The frame's levels of detail (GpuModel::frameLevels, framePrimitivesFor): a model seen at a
// few hundred pixels is drawn simplified to a fifth of a half-pixel cell, which removes the
// triangles a modeller spent on flat stretches (the shipped roadster: a third of them) and
// must leave the image as the full mesh draws it, up to a few edge pixels.
#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <limits>

#include <gtest/gtest.h>

#include "gl_test_support.h"
#include "gles_renderer/assets/builtin_shapes.h"
#include "gles_renderer/assets/gltf_model.h"
#include "gles_renderer/ibl_gpu/ibl_pipeline.h"
#include "gles_renderer/scene/camera_projection.h"
#include "gles_renderer/scene/gpu_model.h"
#include "gles_renderer/scene/mesh_pass.h"

namespace lumar {
namespace {

size_t triangles(const std::vector<GpuPrimitive>& primitives)
{
    size_t count = 0;
    for (const GpuPrimitive& p : primitives)
        count += size_t(p.indexCount) / 3;
    return count;
}

GltfModel roadster()
{
    return loadGltfModel(std::filesystem::path(LUMAR_SOURCE_DIR) / "daemon/assets/models/lumar_roadster.glb");
}

TEST(FrameLevels, EachLevelDrawsFewerTrianglesAndTheSizeChoosesOne)
{
    LUMAR_RENDERER_OR_SKIP(renderer, 16, 16); // for its GL context
    (void)renderer;
    const DefaultTextures defaults = makeDefaultTextures();
    const GpuModel car = uploadModel(roadster(), defaults);
    ASSERT_FALSE(car.frameLevels.empty());
    size_t before = triangles(car.primitives);
    int cells = std::numeric_limits<int>::max();
    for (const GpuModel::ProxyLevel& level : car.frameLevels) {
        EXPECT_LT(level.cells, cells) << "finest first";
        cells = level.cells;
        EXPECT_LE(double(triangles(level.primitives)), (1.0 - kFrameLevelMinTriangleSaving) * double(before));
        before = triangles(level.primitives);
    }
    std::printf("roadster: %zu triangles, frame levels", triangles(car.primitives));
    for (const GpuModel::ProxyLevel& level : car.frameLevels)
        std::printf(" %d cells %zu", level.cells, triangles(level.primitives));
    std::printf("\n");

    // Unknown or too large a size: the model itself.
    EXPECT_EQ(&framePrimitivesFor(car, 0.0), &car.primitives);
    EXPECT_EQ(&framePrimitivesFor(car, std::numeric_limits<double>::infinity()), &car.primitives);
    const GpuModel::ProxyLevel& finest = car.frameLevels.front();
    EXPECT_EQ(&framePrimitivesFor(car, 1.01 * kFrameMaxCellPixels * finest.cells), &car.primitives);
    // Within a level's reach: the coarsest that reaches.
    EXPECT_EQ(&framePrimitivesFor(car, kFrameMaxCellPixels * finest.cells), &finest.primitives);
    const GpuModel::ProxyLevel& coarsest = car.frameLevels.back();
    EXPECT_EQ(&framePrimitivesFor(car, 0.5 * kFrameMaxCellPixels * coarsest.cells), &coarsest.primitives);

    // A mesh with nothing flat to merge keeps no level: it would only cost memory.
    const GpuModel sphere = uploadModel(makeUvSphere(48, 24), defaults);
    EXPECT_TRUE(sphere.frameLevels.empty());
}

// The roadster at the size it has in car.toml (~450 px long), lit by a map whose six faces
// hold six colours (every change of a normal shows), drawn at its chosen level and whole.
TEST(FrameLevels, TheChosenLevelDrawsTheImageOfTheFullMesh)
{
    constexpr int kWidth = 640, kHeight = 480;
    LUMAR_RENDERER_OR_SKIP(renderer, 16, 16); // for its GL context
    (void)renderer;
    const DefaultTextures defaults = makeDefaultTextures();
    std::vector<GpuModel> gpu;
    gpu.push_back(uploadModel(roadster(), defaults));
    IblPipeline pipeline;
    IblMaps colours = pipeline.createMaps();
    pipeline.renderMirror(colours, nullptr, [](int face) {
        const float c[6][3] = {{0.9f, 0.2f, 0.2f}, {0.2f, 0.9f, 0.2f}, {0.2f, 0.2f, 0.9f},
                               {0.9f, 0.9f, 0.2f}, {0.2f, 0.9f, 0.9f}, {0.9f, 0.2f, 0.9f}};
        glClearColor(c[face][0], c[face][1], c[face][2], 1.0f);
        glClear(GL_COLOR_BUFFER_BIT);
    });
    pipeline.updateDerivedMaps(colours);
    const std::vector<const IblMaps*> lighting = {&colours};

    const test::FrameTarget target(kWidth, kHeight);
    ASSERT_TRUE(target.complete());

    constexpr double kFocal = 600.0;
    const CameraIntrinsics intrinsics = test::makeIntrinsics(kWidth, kHeight, kFocal, kFocal, 319.5, 239.5);
    FrameUniforms frame;
    frame.clipFromCamera = glm::mat4(clipFromCamera(intrinsics, kWidth, kHeight));
    frame.frameParams = glm::vec4(1.0f, 0.0f, pipeline.rgbm() ? 1.0f : 0.0f, 1.0f);
    // 0.3 m long, 0.4 m away, seen from above at an angle (OpenCV camera: y down, z ahead).
    const GpuModel& car = gpu[0];
    const glm::dvec3 lo(car.boundsMin), hi(car.boundsMax);
    const double longest = std::max({hi.x - lo.x, hi.y - lo.y, hi.z - lo.z});
    glm::dmat4 cameraFromModel = glm::translate(glm::dmat4(1.0), glm::dvec3(0.0, 0.0, 0.4));
    cameraFromModel = glm::rotate(cameraFromModel, glm::radians(-125.0), glm::dvec3(1, 0, 0));
    cameraFromModel = glm::rotate(cameraFromModel, glm::radians(30.0), glm::dvec3(0, 0, 1));
    cameraFromModel = glm::scale(cameraFromModel, glm::dvec3(0.3 / longest));
    cameraFromModel = glm::translate(cameraFromModel, -0.5 * (lo + hi));
    const DrawItem items[] = {{0, cameraFromModel}};
    const double pixels = MeshPass::modelPixels(items[0], car, kFocal);
    ASSERT_NE(&framePrimitivesFor(car, pixels), &car.primitives) << pixels << " px: no level chosen";

    MeshPass meshes;
    const auto draw = [&](double focalPixels) {
        glClearColor(0.0f, 0.0f, 0.0f, 0.0f);
        glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
        meshes.draw(frame, gpu, items, lighting, -1, MeshPass::Phantoms::Shaded, MeshPass::Detail::Full, focalPixels);
        std::vector<uint8_t> rgba(size_t(kWidth) * kHeight * 4);
        glReadPixels(0, 0, kWidth, kHeight, GL_RGBA, GL_UNSIGNED_BYTE, rgba.data());
        return rgba;
    };
    const std::vector<uint8_t> whole = draw(0.0); // unknown size: the model itself
    const std::vector<uint8_t> chosen = draw(kFocal);
    glBindFramebuffer(GL_FRAMEBUFFER, 0);

    size_t covered = 0, differing = 0, far = 0;
    double difference = 0.0;
    for (size_t i = 0; i < whole.size(); i += 4) {
        const auto blank = [](const uint8_t* p) { return p[0] == 0 && p[1] == 0 && p[2] == 0 && p[3] == 0; };
        if (blank(&whole[i]) && blank(&chosen[i]))
            continue; // background in both
        ++covered;
        int most = 0;
        for (size_t c = 0; c < 3; ++c) {
            const int d = std::abs(int(whole[i + c]) - int(chosen[i + c]));
            most = std::max(most, d);
            difference += d;
        }
        differing += most > 8 ? 1 : 0;
        far += most > 64 ? 1 : 0;
    }
    const double share = 100.0 * double(differing) / double(covered);
    std::printf("roadster at %.0f px: %zu covered pixels, %zu (%.3f %%) differ by more than 8 codes, %zu by more "
                "than 64; mean difference %.3f codes\n",
                pixels, covered, differing, share, far, difference / (3.0 * double(covered)));
    ASSERT_GT(covered, size_t(20000)) << "the car should fill a good part of the frame";
    // Silhouette pixels whose centre the tenth of a pixel moves across: a handful.
    EXPECT_LT(share, 0.2);
    EXPECT_LT(difference / (3.0 * double(covered)), 0.2);
}

} // namespace
} // namespace lumar
