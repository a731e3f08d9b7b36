// A reload in place (Pipeline::prepareReload + applyReload, what `lumar run` does on SIGHUP or a
// file change): the camera keeps its frame sequence, the GL context is kept where the new
// configuration allows it, the output shows the new scene as a pipeline built from scratch
// for it would, and a bad model leaves the running scene untouched.
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <memory>
#include <string>

#include <EGL/egl.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include "config/config.h"
#include "core/error.h"
#include "pipeline.h"

namespace lumar {
namespace {

// A fake camera looking at tag 0 with one object on it, sized to cover a good part of the
// 320x240 frame. Environment maps off: llvmpipe renders them slowly and they are not what is
// tested here.
std::string sceneText(const std::string& model, const std::string& extra = "")
{
    return "[camera]\nwidth = 320\nheight = 240\n"
           "[[markers]]\nid = 0\nsize = 0.16\n"
           "[[objects]]\nname = \"thing\"\nmodel = \"" +
           model +
           "\"\nmaterial = \"car_paint\"\nmarker = 0\nsize = 0.12\n"
           "[rendering]\nenvironment_maps = \"off\"\n" +
           extra;
}

Config scene(const std::string& model, const std::string& extra = "")
{
    return parseConfig(sceneText(model, extra), "scene.toml", std::filesystem::temp_directory_path());
}

// The pipeline, or null with the reason when this machine has no EGL/GLES 3 (the test skips).
std::unique_ptr<Pipeline> makePipeline(const Config& config, std::string& reason)
{
    try {
        return std::make_unique<Pipeline>(config);
    } catch (const RuntimeError& e) {
        reason = e.what();
        return nullptr;
    }
}

#define LUMAR_PIPELINE_OR_SKIP(variable, config)                                                                       \
    std::string variable##Reason;                                                                                      \
    const std::unique_ptr<Pipeline> variable##Owner = makePipeline(config, variable##Reason);                          \
    if (!variable##Owner)                                                                                              \
        GTEST_SKIP() << "no GLES 3 renderer: " << variable##Reason;                                                    \
    Pipeline& variable = *variable##Owner

// Steps `frames` frames; the last frame's report.
FrameReport stepFrames(Pipeline& pipeline, int frames)
{
    FrameReport report;
    for (int i = 0; i < frames; ++i)
        EXPECT_TRUE(pipeline.step(report));
    return report;
}

// Pixels whose channels differ by more than 24 code values somewhere.
int differingPixels(const Image8& a, const Image8& b)
{
    EXPECT_EQ(a.data.size(), b.data.size());
    int count = 0;
    for (size_t i = 0; i + 2 < a.data.size() && i + 2 < b.data.size(); i += 3) {
        bool differs = false;
        for (size_t c = 0; c < 3; ++c)
            differs = differs || std::abs(int(a.data[i + c]) - int(b.data[i + c])) > 24;
        count += differs ? 1 : 0;
    }
    return count;
}

constexpr int kFramesBefore = 4;

TEST(PipelineReload, ModelSwapKeepsCameraAndGlContextAndShowsTheNewModel)
{
    LUMAR_PIPELINE_OR_SKIP(running, scene("builtin:sphere"));
    EXPECT_EQ(stepFrames(running, kFramesBefore).objectsDrawn, 1);
    const EGLContext contextBefore = eglGetCurrentContext();
    ASSERT_NE(contextBefore, EGL_NO_CONTEXT);

    const Config cube = scene("builtin:cube");
    ASSERT_TRUE(running.keepsCamera(cube));
    const ReloadSummary summary = running.applyReload(running.prepareReload(cube));
    EXPECT_TRUE(summary.keptRenderer);
    EXPECT_TRUE(summary.keptTracker);
    EXPECT_TRUE(summary.keptEnvironment);
    EXPECT_EQ(summary.modelsBefore, 1u);
    EXPECT_EQ(summary.modelsAfter, 1u);

    // The same camera: its sequence goes on (a new one starts again at 0).
    const FrameReport after = stepFrames(running, 1);
    EXPECT_EQ(after.sequence, uint64_t(kFramesBefore));
    EXPECT_EQ(after.objectsDrawn, 1);
    // The same GL context renders (a new one would have been created while the old one
    // still existed, so it cannot have the same handle).
    EXPECT_EQ(eglGetCurrentContext(), contextBefore);

    // The frame shows the cube as a pipeline made for the cube shows that frame, and not the
    // sphere any more.
    LUMAR_PIPELINE_OR_SKIP(freshCube, cube);
    stepFrames(freshCube, kFramesBefore + 1);
    LUMAR_PIPELINE_OR_SKIP(freshSphere, scene("builtin:sphere"));
    stepFrames(freshSphere, kFramesBefore + 1);
    const int shapeDifference = differingPixels(freshCube.output(), freshSphere.output());
    ASSERT_GT(shapeDifference, 100) << "the test scene does not tell a cube from a sphere";
    EXPECT_LE(differingPixels(running.output(), freshCube.output()), shapeDifference / 50);
}

TEST(PipelineReload, RenderingChangeKeepsTheCameraButMakesANewGlContext)
{
    LUMAR_PIPELINE_OR_SKIP(running, scene("builtin:sphere"));
    stepFrames(running, kFramesBefore);
    const EGLContext contextBefore = eglGetCurrentContext();

    // environment_map_size is fixed when the renderer is created; the filter setting is the
    // tracker's.
    const Config next =
        scene("builtin:sphere", "environment_map_size = 32\n[tracking]\nfilter = false\n[[objects]]\nname = \"two\"\n"
                                "model = \"builtin:cube\"\nmarker = 0\noffset = [0.1, 0.0, 0.0]\nsize = 0.04\n");
    ASSERT_TRUE(running.keepsCamera(next));
    const ReloadSummary summary = running.applyReload(running.prepareReload(next));
    EXPECT_FALSE(summary.keptRenderer);
    EXPECT_FALSE(summary.keptTracker);
    EXPECT_FALSE(summary.keptEnvironment) << "a new context needs the environment again";
    EXPECT_EQ(summary.modelsAfter, 2u);

    const FrameReport after = stepFrames(running, 1);
    EXPECT_EQ(after.sequence, uint64_t(kFramesBefore));
    EXPECT_NE(eglGetCurrentContext(), contextBefore);
    EXPECT_EQ(after.objectsDrawn, 2);
}

TEST(PipelineReload, OnlyACameraChangeNeedsANewCamera)
{
    const Config running = scene("builtin:sphere");
    Config next = running;
    next.objects[0].model = "builtin:cube";
    next.tracking.quadDecimate = 1.0;
    next.rendering.environmentMaps = "every_frame";
    next.output.path = "elsewhere.y4m";
    EXPECT_TRUE(next.camera == running.camera);
    // Any [camera] key, nested ones included, is a change.
    next.camera.seed = 2;
    EXPECT_FALSE(next.camera == running.camera);
    next.camera = running.camera;
    next.camera.fakeTags[0].position.x = 0.01;
    EXPECT_FALSE(next.camera == running.camera);
    next.camera = running.camera;
    next.camera.controls.gain = 3;
    EXPECT_FALSE(next.camera == running.camera);

    LUMAR_PIPELINE_OR_SKIP(pipeline, running);
    const Config wider = parseConfig("[camera]\nwidth = 640\nheight = 480\n", "scene.toml", "/");
    EXPECT_FALSE(pipeline.keepsCamera(wider));
    EXPECT_THROW((void)pipeline.prepareReload(wider), std::logic_error);
}

TEST(PipelineReload, ABadModelLeavesTheRunningSceneAsItWas)
{
    const auto dir = std::filesystem::temp_directory_path() / ("lumar-pipeline-reload-" + std::to_string(::getpid()));
    std::filesystem::create_directories(dir);
    std::ofstream(dir / "broken.glb") << "not a glTF file";

    LUMAR_PIPELINE_OR_SKIP(running, scene("builtin:sphere"));
    stepFrames(running, kFramesBefore);
    const EGLContext contextBefore = eglGetCurrentContext();
    // A valid file naming a model that does not load, and a rendering change, so a new
    // renderer would have been made had the model loaded.
    const Config bad =
        parseConfig(sceneText((dir / "broken.glb").string(), "environment_map_size = 32\n"), "scene.toml", dir);
    EXPECT_THROW((void)running.prepareReload(bad), InputError);
    std::filesystem::remove_all(dir);

    const FrameReport after = stepFrames(running, 1);
    EXPECT_EQ(after.sequence, uint64_t(kFramesBefore));
    EXPECT_EQ(after.objectsDrawn, 1);
    EXPECT_EQ(eglGetCurrentContext(), contextBefore);
    LUMAR_PIPELINE_OR_SKIP(freshSphere, scene("builtin:sphere"));
    stepFrames(freshSphere, kFramesBefore + 1);
    EXPECT_EQ(differingPixels(running.output(), freshSphere.output()), 0) << "the sphere scene goes on unchanged";
}

} // namespace
} // namespace lumar
