// The per-object dynamic environment maps in a scene (DESIGN.md §6.1): a chrome sphere
// beside a red emissive cube. The sphere's map shows the cube and its pixels that face the
// cube turn red (inter-reflection); no object appears in its own map, even double-sided;
// the update policies re-render the maps they promise.
#include <filesystem>

#include <glm/gtc/matrix_transform.hpp>
#include <gtest/gtest.h>

#include "gl_readback.h"
#include "gl_test_support.h"
#include "gles_renderer/assets/builtin_shapes.h"
#include "gles_renderer/assets/lafortune_material.h"
#include "gles_renderer/ibl/cube_face_camera.h"
#include "gles_renderer/ibl_gpu/ibl_pipeline.h"
#include "gles_renderer/scene/camera_projection.h"
#include "gles_renderer/scene/environment_probes.h"
#include "gles_renderer/scene/gpu_model.h"
#include "gles_renderer/scene/mesh_pass.h"

namespace lumar {
namespace {

constexpr int kWidth = 160, kHeight = 120;

const CameraIntrinsics& intrinsics()
{
    static const CameraIntrinsics k = test::makeIntrinsics(kWidth, kHeight, 200, 200, 79.5, 59.5);
    return k;
}

GltfModel chromeSphere()
{
    GltfModel model = makeUvSphere(48, 24);
    model.materials[0].hasLafortune = true;
    model.materials[0].lafortune = *materialPreset("chrome");
    return model;
}

GltfModel redLamp()
{
    GltfModel model = makeCube();
    GltfMaterial& m = model.materials[0];
    m.baseColorFactor = glm::vec4(0, 0, 0, 1);
    m.emissiveFactor = glm::vec3(3.0f, 0.0f, 0.0f);
    m.doubleSided = true; // visible from inside: only hiding the owner keeps it out of its own map
    return model;
}

glm::dmat4 placed(double x, double y, double z, double size)
{
    return test::translation(x, y, z) * glm::dmat4(glm::dmat3(size));
}

struct Scene {
    std::vector<DrawItem> items;
};

Scene makeScene(SceneRenderer& renderer)
{
    renderer.setEnvironment(test::uniformEnvironment(0.2f), 1.0f);
    const ModelId sphere = renderer.addModel(chromeSphere());
    const ModelId lamp = renderer.addModel(redLamp());
    return {{{sphere, placed(-0.06, 0.0, 0.5, 0.1), 0}, {lamp, placed(0.07, 0.0, 0.5, 0.08), 1}}};
}

glm::vec3 maxOf(const ImageF& face)
{
    glm::vec3 m(0.0f);
    for (size_t i = 0; i < face.data.size(); i += 3)
        m = glm::max(m, glm::vec3(face.data[i], face.data[i + 1], face.data[i + 2]));
    return m;
}

glm::vec3 maxOf(const CubeMapF& cube)
{
    glm::vec3 m(0.0f);
    for (const ImageF& face : cube.faces)
        m = glm::max(m, maxOf(face));
    return m;
}

TEST(EnvironmentProbes, EachMapShowsTheOtherObjectsButNeverItsOwner)
{
    LUMAR_RENDERER_OR_SKIP(renderer, kWidth, kHeight);
    const Scene scene = makeScene(renderer);
    // Two frames: the faces show the neighbours with their maps of the frame before (the
    // bounce checked at the end needs the sphere's first maps).
    for (int frame = 0; frame < 2; ++frame)
        renderer.render(test::solidImage(kWidth, kHeight, 0, 0, 0), intrinsics(), scene.items);
    const IblSettings settings;
    ASSERT_NE(renderer.objectMaps(0), nullptr);
    ASSERT_NE(renderer.objectMaps(1), nullptr);
    const CubeMapF sphereSees = test::readMirrorMap(*renderer.objectMaps(0), settings.mirrorSize);
    const CubeMapF lampSees = test::readMirrorMap(*renderer.objectMaps(1), settings.mirrorSize);
    // The environment frame is the camera's here (no rotation set): the lamp lies along +x
    // of the sphere. The sphere's map holds the lamp's emission (3.0) in its +X face.
    EXPECT_GT(maxOf(sphereSees.faces[0]).r, 2.5f);
    // Facing away from each other, each map sees the grey environment alone: an owner drawn
    // into its own map (the lamp is double-sided, so visible from inside) would fill them.
    EXPECT_NEAR(maxOf(sphereSees.faces[1]).r, 0.2f, 0.01f);
    EXPECT_NEAR(maxOf(lampSees.faces[0]).r, 0.2f, 0.01f);
    EXPECT_NEAR(maxOf(lampSees.faces[0]).g, 0.2f, 0.01f);
    // Towards -x the lamp's map sees the chrome sphere, which mirrors the lamp back from its
    // own (previous-bounce) map: one bounce of inter-reflection, 0.95 x 3.0 at most.
    EXPECT_GT(maxOf(lampSees.faces[1]).r, 1.0f);
    EXPECT_LT(maxOf(lampSees).r, 3.0f);
}

TEST(EnvironmentProbes, MirrorSphereFacingARedLampTurnsRed)
{
    // The sphere's point whose normal is (0.7, 0, -0.7) reflects the view ray towards +x,
    // into the lamp: at (-0.025, 0, 0.465) it projects to about pixel (69, 60).
    const auto pixelFacingTheLamp = [](SceneRenderer& renderer, const Scene& scene) {
        Image8 out;
        for (int frame = 0; frame < 2; ++frame) // a second bounce changes nothing here
            renderer.render(test::solidImage(kWidth, kHeight, 0, 0, 0), intrinsics(), scene.items);
        renderer.readback(out);
        const uint8_t* p = out.at(69, 60);
        return glm::ivec3(p[0], p[1], p[2]);
    };
    glm::ivec3 dynamicMaps, environmentOnly;
    {
        LUMAR_RENDERER_OR_SKIP(renderer, kWidth, kHeight);
        dynamicMaps = pixelFacingTheLamp(renderer, makeScene(renderer));
    }
    {
        RenderOptions options;
        options.environmentMaps.dynamic = false;
        LUMAR_RENDERER_OR_SKIP(renderer, kWidth, kHeight, options);
        environmentOnly = pixelFacingTheLamp(renderer, makeScene(renderer));
    }
    glm::ivec3 rgbmMaps;
    {
        RenderOptions options;
        options.environmentMaps.ibl.forceRgbm = true; // the fallback without float targets
        LUMAR_RENDERER_OR_SKIP(renderer, kWidth, kHeight, options);
        rgbmMaps = pixelFacingTheLamp(renderer, makeScene(renderer));
    }
    // The RGBM maps agree to a few code values: bilinear filtering interpolates encoded
    // texels across the lamp's edge (measured: red equal within 3; green and blue, at the
    // dark end where sRGB spreads radiance over many codes, 23 vs 13, i.e. 0.0086 against
    // 0.0040 in radiance), so green and blue are compared as radiance.
    const auto radiance = [](int code) { return test::srgbDecode(code / 255.0); };
    EXPECT_NEAR(rgbmMaps.x, dynamicMaps.x, 3);
    EXPECT_NEAR(radiance(rgbmMaps.y), radiance(dynamicMaps.y), 0.008);
    EXPECT_NEAR(radiance(rgbmMaps.z), radiance(dynamicMaps.z), 0.008);
    SCOPED_TRACE(testing::Message() << "dynamic (" << dynamicMaps.x << ", " << dynamicMaps.y << ", " << dynamicMaps.z
                                    << "), environment only (" << environmentOnly.x << ", " << environmentOnly.y << ", "
                                    << environmentOnly.z << ")");
    EXPECT_GT(dynamicMaps.x, 200);                        // the lamp's red, tone-mapped
    EXPECT_LT(dynamicMaps.y, environmentOnly.y);          // the grey it hides
    EXPECT_NEAR(environmentOnly.x, environmentOnly.y, 2); // plain grey reflection
}

// The maps are drawn in banks (ibl_maps.h), every object's faces in one pass: a face shows
// its neighbours shaded with their maps as the previous frame left them, never with the
// texture being drawn (nor what this pass drew into it). The lamp sees the chrome sphere:
// after the first frame the sphere still wore the real environment's grey maps (no red in
// the lamp's map); later it wears its own maps, which hold the red lamp. When the lamp turns
// into a grey cube, the sphere's maps of the frame before still show it red for one frame.
TEST(EnvironmentProbes, NeighboursWearTheirMapsOfThePreviousFrame)
{
    LUMAR_RENDERER_OR_SKIP(renderer, kWidth, kHeight);
    Scene scene = makeScene(renderer);
    GltfModel greyCube = makeCube();
    greyCube.materials[0].baseColorFactor = glm::vec4(0.2f, 0.2f, 0.2f, 1.0f);
    const ModelId grey = renderer.addModel(greyCube);
    const IblSettings settings;
    const auto lampSeesOfSphere = [&] {
        renderer.render(test::solidImage(kWidth, kHeight, 0, 0, 0), intrinsics(), scene.items);
        EXPECT_NE(renderer.objectMaps(1), nullptr);
        // The sphere lies along -x of the lamp: its -X face.
        return maxOf(test::readMirrorMap(*renderer.objectMaps(1), settings.mirrorSize).faces[1]);
    };
    const glm::vec3 first = lampSeesOfSphere();
    EXPECT_NEAR(first.r, 0.2f, 0.02f) << "the sphere wore this frame's maps already";
    EXPECT_NEAR(first.r, first.g, 0.02f);
    for (int frame = 2; frame <= 3; ++frame) {
        const glm::vec3 later = lampSeesOfSphere();
        EXPECT_GT(later.r, first.r + 0.2f) << "frame " << frame << ": the sphere does not reflect the lamp";
        EXPECT_NEAR(later.g, first.g, 0.02f) << "frame " << frame;
    }
    scene.items[1].model = grey; // the same object (slot), no longer a lamp
    const glm::vec3 turned = lampSeesOfSphere();
    EXPECT_GT(turned.r, first.r + 0.2f) << "the sphere wore the maps drawn in this frame's pass";
    const glm::vec3 after = lampSeesOfSphere();
    EXPECT_LT(after.r, first.r + 0.05f) << "the sphere still shows the lamp a frame later";
}

TEST(EnvironmentProbes, PoliciesUpdateTheMapsTheyPromise)
{
    const auto updatesPerFrame = [](EnvironmentMapPolicy policy, int frames) {
        RenderOptions options;
        options.environmentMaps.policy = policy;
        options.environmentMaps.everyK = 2;
        options.environmentMaps.budgetMs = 0.001; // fits nothing: still one per frame
        auto renderer = SceneRenderer::create(kWidth, kHeight, options);
        const Scene scene = makeScene(*renderer);
        std::vector<int> counts;
        for (int i = 0; i < frames; ++i) {
            renderer->render(test::solidImage(kWidth, kHeight, 0, 0, 0), intrinsics(), scene.items);
            counts.push_back(renderer->lastStats().mapsUpdated);
        }
        return counts;
    };
    try {
        EXPECT_EQ(updatesPerFrame(EnvironmentMapPolicy::EveryFrame, 3), (std::vector<int>{2, 2, 2}));
        // Both are new on frame 0; then one of the two each frame, staggered.
        EXPECT_EQ(updatesPerFrame(EnvironmentMapPolicy::EveryKFrames, 4), (std::vector<int>{2, 1, 1, 1}));
        EXPECT_EQ(updatesPerFrame(EnvironmentMapPolicy::Budget, 3), (std::vector<int>{1, 1, 1}));
        // A still scene: three updates for the bounces, then none.
        EXPECT_EQ(updatesPerFrame(EnvironmentMapPolicy::OnChange, 5), (std::vector<int>{2, 2, 2, 0, 0}));
    } catch (const RuntimeError& e) {
        GTEST_SKIP() << "no GLES 3 renderer: " << e.what();
    }
}

// An object's set of maps derives only the maps its materials read (EnvironmentMapReads): the
// chrome sphere's shading reads its mirror map alone, so its SH projection, diffuse map and
// glossy prefilters are not built; the lamp (no diffuse term: black; glossiness above 1/4:
// makeCube's roughness 0.5, n = 30) reads the glossy maps but not the diffuse one. An object whose material changes to
// one that reads more (the sphere turned into a grey diffuse cube) gets them rebuilt on that very frame, even where its
// policy would have kept its maps for a few frames: never a map that was never drawn. Its diffuse map then shows the
// grey environment (0.2) on its far side from the lamp.
TEST(EnvironmentProbes, OnlyTheMapsAnObjectsMaterialsReadAreDerived)
{
    RenderOptions options;
    options.environmentMaps.policy = EnvironmentMapPolicy::EveryKFrames;
    options.environmentMaps.everyK = 3; // object k is due on frames where (frame + k) % 3 == 0
    LUMAR_RENDERER_OR_SKIP(renderer, kWidth, kHeight, options);
    Scene scene = makeScene(renderer);
    GltfModel greyCube = makeCube();
    greyCube.materials[0].baseColorFactor = glm::vec4(0.2f, 0.2f, 0.2f, 1.0f);
    const ModelId grey = renderer.addModel(greyCube);
    const auto render = [&] {
        renderer.render(test::solidImage(kWidth, kHeight, 0, 0, 0), intrinsics(), scene.items);
        return renderer.lastStats();
    };
    // Frame 0: both are new; the sphere's set gets its mirror map alone, the lamp's its glossy
    // maps too.
    const RenderStats first = render();
    EXPECT_EQ(first.mapsUpdated, 2);
    EXPECT_EQ(first.shProjected, 0);
    EXPECT_EQ(first.mapsPrefiltered, 1);
    render(); // frame 1: nobody is due
    render(); // frame 2: the lamp
    EXPECT_EQ(renderer.lastStats().mapsUpdated, 1);
    EXPECT_EQ(renderer.lastStats().mapsPrefiltered, 1);
    render(); // frame 3: the sphere, its mirror map alone
    EXPECT_EQ(renderer.lastStats().mapsUpdated, 1);
    EXPECT_EQ(renderer.lastStats().shProjected, 0);
    EXPECT_EQ(renderer.lastStats().mapsPrefiltered, 0);
    // Frame 4, nobody due: the sphere turns into a grey cube, which reads the diffuse map (its
    // diffuse term) and the glossy ones.
    scene.items[0].model = grey;
    const RenderStats turned = render();
    EXPECT_EQ(turned.mapsUpdated, 1) << "the turned object's maps were not rebuilt at once";
    EXPECT_EQ(turned.shProjected, 1);
    EXPECT_EQ(turned.mapsPrefiltered, 1);
    const IblMaps* maps = renderer.objectMaps(0);
    ASSERT_NE(maps, nullptr);
    const IblSettings settings;
    const IblTextures t = maps->textures();
    const CubeMapF diffuse = test::readCubeAtlas(t.diffuse, settings.diffuseSize, 0, t.slot, t.slots);
    // The lamp lies along +x: the -X face's hemisphere does not see it.
    const glm::vec3 far = maxOf(diffuse.faces[1]);
    EXPECT_NEAR(far.r, 0.2f, 0.03f);
    EXPECT_NEAR(far.g, 0.2f, 0.03f);
}

// Neighbours are drawn only into the faces their bounding box reaches (EnvironmentProbes'
// per-face culling): a long bar lying along +x of a small cube's centre shows in the cube's
// +X face alone, where a bounding sphere (the bar's is as wide as it is long) reached into
// four more. Every face it is drawn into costs all its vertices; the culling must keep the
// one face that shows it.
TEST(EnvironmentProbes, NeighboursAreDrawnOnlyIntoTheFacesTheirBoxReaches)
{
    LUMAR_RENDERER_OR_SKIP(renderer, kWidth, kHeight);
    renderer.setEnvironment(test::uniformEnvironment(0.2f), 1.0f);
    const ModelId cube = renderer.addModel(makeCube());
    const ModelId bar = renderer.addModel(redLamp());
    // The bar from 0.05 to 0.45 m along +x of the cube, 1 cm thick.
    const std::vector<DrawItem> items{
        {cube, placed(0.0, 0.0, 0.5, 0.02), 0},
        {bar, test::translation(0.25, 0.0, 0.5) * glm::scale(glm::dmat4(1.0), glm::dvec3(0.4, 0.01, 0.01)), 1}};
    for (int frame = 0; frame < 2; ++frame)
        renderer.render(test::solidImage(kWidth, kHeight, 0, 0, 0), intrinsics(), items);
    // Per map, the other object is drawn into one face of six: five culled each.
    EXPECT_EQ(renderer.lastStats().facesCulled, 10);
    ASSERT_NE(renderer.objectMaps(0), nullptr);
    const CubeMapF cubeSees = test::readMirrorMap(*renderer.objectMaps(0), IblSettings().mirrorSize);
    EXPECT_GT(maxOf(cubeSees.faces[0]).r, 2.5f) << "the bar is in the +X face";
    for (int face = 1; face < kCubeFaces; ++face)
        EXPECT_NEAR(maxOf(cubeSees.faces[size_t(face)]).r, 0.2f, 0.01f) << "face " << face;
}

// OnChange follows the scene, not the camera: turning the camera (and with it the
// environment's rotation) around still objects changes nothing in their maps; moving one
// object re-renders both maps.
TEST(EnvironmentProbes, OnChangeIgnoresTheCameraAndFollowsTheObjects)
{
    RenderOptions options;
    options.environmentMaps.policy = EnvironmentMapPolicy::OnChange;
    LUMAR_RENDERER_OR_SKIP(renderer, kWidth, kHeight, options);
    Scene scene = makeScene(renderer);
    const auto frame = [&](const glm::dmat4& cameraMotion) {
        std::vector<DrawItem> moved = scene.items;
        for (DrawItem& item : moved)
            item.cameraFromModel = cameraMotion * item.cameraFromModel;
        // The environment stays fixed to the world: it turns with the inverse camera motion.
        renderer.setEnvironmentRotation(glm::inverse(glm::dmat3(cameraMotion)));
        renderer.render(test::solidImage(kWidth, kHeight, 0, 0, 0), intrinsics(), moved);
        return renderer.lastStats().mapsUpdated;
    };
    for (int i = 0; i < 3; ++i)
        EXPECT_EQ(frame(glm::dmat4(1.0)), 2);
    const glm::dmat4 turned = glm::rotate(glm::dmat4(1.0), glm::radians(20.0), glm::dvec3(0, 1, 0)) *
                              glm::translate(glm::dmat4(1.0), glm::dvec3(0.03, -0.02, 0.05));
    EXPECT_EQ(frame(turned), 0) << "the camera moved, the scene did not";
    scene.items[1].cameraFromModel = test::translation(0.0, 0.05, 0.0) * scene.items[1].cameraFromModel;
    EXPECT_EQ(frame(turned), 2) << "the lamp moved";
}

// Draws items round a probe centre at the origin of the cube frame into a map's six faces,
// as EnvironmentProbes does, lit by a grey environment (a cleared map). Needs a context.
struct FaceRig {
    DefaultTextures defaults = makeDefaultTextures();
    std::vector<GpuModel> gpu;
    IblPipeline pipeline;
    int size = pipeline.settings().mirrorSize;
    IblMaps grey = pipeline.createMaps();
    MeshPass meshes;

    FaceRig()
    {
        pipeline.renderMirror(grey, nullptr, [](int) {
            glClearColor(0.5f, 0.45f, 0.4f, 1.0f);
            glClear(GL_COLOR_BUFFER_BIT);
        });
        pipeline.updateDerivedMaps(grey);
    }
    // Model `model` with its longest side `longest` metres, centred at `at`, turned about y.
    [[nodiscard]] DrawItem place(size_t model, glm::dvec3 at, double longest, double turnDegrees) const
    {
        const glm::dvec3 lo(gpu[model].boundsMin), hi(gpu[model].boundsMax);
        const glm::dvec3 extent = hi - lo;
        glm::dmat4 m = glm::translate(glm::dmat4(1.0), at);
        m = glm::rotate(m, glm::radians(turnDegrees), glm::dvec3(0, 1, 0));
        m = glm::scale(m, glm::dvec3(longest / std::max({extent.x, extent.y, extent.z})));
        return DrawItem{ModelId(model), glm::translate(m, -0.5 * (lo + hi))};
    }
    void render(IblMaps& maps, const IblMaps* backdrop, const std::vector<DrawItem>& cubeItems, MeshPass::Detail detail,
                double focalPixels, MeshPass::Phantoms phantoms = MeshPass::Phantoms::Shaded)
    {
        const std::vector<const IblMaps*> lighting(cubeItems.size(), &grey);
        pipeline.renderMirror(maps, backdrop, [&](int face) {
            std::vector<DrawItem> items = cubeItems;
            for (DrawItem& item : items)
                item.cameraFromModel = glm::dmat4(faceCameraFromCube(face)) * item.cameraFromModel;
            const FrameUniforms frame = cubeFaceFrameUniforms(face, size, pipeline.rgbm());
            meshes.draw(frame, gpu, items, lighting, -1, phantoms, detail, focalPixels);
        });
    }
    [[nodiscard]] CubeMapF read(const IblMaps& maps) const
    {
        return pipeline.rgbm() ? test::readCubeAtlasRgbm(maps.mirror.name(), size)
                               : test::readCubeAtlas(maps.mirror.name(), size);
    }
    [[nodiscard]] CubeMapF render(const std::vector<DrawItem>& cubeItems, MeshPass::Detail detail, double focalPixels)
    {
        IblMaps maps = pipeline.createMaps();
        render(maps, &grey, cubeItems, detail, focalPixels);
        return read(maps);
    }
};

// Neighbours are drawn into the faces as simplified stand-ins whose level follows their size
// in the face (proxyLevelFor): a model a few pixels wide gets a coarse level. Their maps must
// stay as close to the full meshes' as the finest stand-in's (the level every neighbour got
// before), at the sizes neighbours have in the car scene (12 to 45 pixels of a 64-px face).
TEST(EnvironmentProbes, StandInsChosenBySizeLookLikeTheFullMeshes)
{
    LUMAR_RENDERER_OR_SKIP(renderer, kWidth, kHeight); // for its GL context
    (void)renderer;
    FaceRig rig;
    const std::filesystem::path models = std::filesystem::path(LUMAR_SOURCE_DIR) / "daemon/assets/models";
    rig.gpu.push_back(uploadModel(loadGltfModel(models / "lumar_roadster.glb"), rig.defaults));
    rig.gpu.push_back(uploadModel(loadGltfModel(models / "CesiumMilkTruck.glb"), rig.defaults));
    rig.gpu.push_back(uploadModel(chromeSphere(), rig.defaults));
    ASSERT_GT(rig.gpu[0].proxyLevels.size(), 2u);
    ASSERT_GT(rig.gpu[2].proxyLevels.size(), 2u);

    // The three models round the probe's centre, each in a face of its own, at (longest
    // side, distance) of the car scene's neighbours.
    const std::vector<DrawItem> items{
        rig.place(0, {0.21, 0.0, 0.0}, 0.3, 30.0), rig.place(1, {0.0, 0.0, 0.23}, 0.16, 90.0),
        rig.place(2, {-0.2, 0.0, 0.0}, 0.1, 0.0), rig.place(2, {0.0, 0.0, -0.4}, 0.1, 0.0)};
    const CubeMapF full = rig.render(items, MeshPass::Detail::Full, 0.0);
    const CubeMapF finest = rig.render(items, MeshPass::Detail::Proxy, 0.0); // unknown size: the finest level
    const CubeMapF chosen = rig.render(items, MeshPass::Detail::Proxy, faceIntrinsics(rig.size).fx);
    // Mean absolute difference from the full meshes over the texels any of the three
    // renders covers (differs from the grey backdrop), in % of the full meshes' mean there.
    const CubeMapF backdrop = rig.read(rig.grey);
    const auto error = [&](const CubeMapF& map) {
        double difference = 0.0, radiance = 0.0;
        for (size_t f = 0; f < size_t(kCubeFaces); ++f) {
            const std::vector<float>&a = full.faces[f].data, &b = map.faces[f].data, &g = backdrop.faces[f].data;
            for (size_t i = 0; i + 2 < a.size(); i += 3) {
                bool covered = false;
                for (size_t c = 0; c < 3; ++c)
                    covered = covered || std::abs(a[i + c] - g[i + c]) > 1e-3f ||
                              std::abs(finest.faces[f].data[i + c] - g[i + c]) > 1e-3f ||
                              std::abs(chosen.faces[f].data[i + c] - g[i + c]) > 1e-3f;
                if (covered)
                    for (size_t c = 0; c < 3; ++c) {
                        difference += std::abs(double(b[i + c]) - a[i + c]);
                        radiance += a[i + c];
                    }
            }
        }
        return 100.0 * difference / radiance;
    };
    const double finestError = error(finest), chosenError = error(chosen);
    std::printf("stand-ins against full meshes, mean |difference| in %% of the mean: finest %.3f, chosen %.3f\n",
                finestError, chosenError);
    // Measured on llvmpipe: finest 6.1 %, chosen 6.5 % with meshoptimizer's stand-ins (14.8 and
    // 15.0 % with the vertex clustering before them; edge texels dominate). The level rule must
    // not add more than a tenth.
    EXPECT_LT(finestError, 20.0);
    EXPECT_LT(chosenError, 1.1 * finestError);
}

// EnvironmentProbes' phantom layer: the phantoms shaded over the backdrop into a map of
// their own, then that map as the backdrop of a pass that draws the phantoms into depth
// alone and the rest shaded. That must give the map of one pass that shades everything,
// with neighbours in front of and behind a phantom.
TEST(EnvironmentProbes, PhantomLayerUnderDepthOnlyPhantomsEqualsOneShadedPass)
{
    LUMAR_RENDERER_OR_SKIP(renderer, kWidth, kHeight); // for its GL context
    (void)renderer;
    FaceRig rig;
    const std::filesystem::path models = std::filesystem::path(LUMAR_SOURCE_DIR) / "daemon/assets/models";
    rig.gpu.push_back(uploadModel(loadGltfModel(models / "CesiumMilkTruck.glb"), rig.defaults));
    GltfModel table = makeCube();
    table.materials[0].baseColorFactor = glm::vec4(0.45f, 0.25f, 0.12f, 1.0f);
    table.materials[0].roughnessFactor = 1.0f;
    rig.gpu.push_back(uploadModel(table, rig.defaults));
    // A table top below the centre (cube +y is down in the face cameras' OpenCV sense, so
    // any side works), a truck standing on it in front and one under it, hidden.
    std::vector<DrawItem> items{rig.place(0, {0.15, 0.05, 0.1}, 0.16, 30.0), rig.place(0, {0.0, 0.2, 0.0}, 0.16, 0.0)};
    DrawItem phantom{1,
                     glm::translate(glm::dmat4(1.0), {0.0, 0.1, 0.0}) * glm::scale(glm::dmat4(1.0), {1.2, 0.02, 0.8})};
    phantom.phantom = true;
    items.push_back(phantom);
    const double focal = faceIntrinsics(rig.size).fx;

    IblMaps layer = rig.pipeline.createMaps();
    rig.render(layer, &rig.grey, {phantom}, MeshPass::Detail::Proxy, focal);
    IblMaps layered = rig.pipeline.createMaps();
    rig.render(layered, &layer, items, MeshPass::Detail::Proxy, focal, MeshPass::Phantoms::DepthOnly);
    const CubeMapF composed = rig.read(layered);
    const CubeMapF onePass = rig.render(items, MeshPass::Detail::Proxy, focal);
    const CubeMapF backdrop = rig.read(rig.grey);
    size_t differing = 0, covered = 0, total = 0;
    for (size_t f = 0; f < size_t(kCubeFaces); ++f)
        for (size_t i = 0; i < onePass.faces[f].data.size(); ++i, ++total) {
            differing += std::abs(composed.faces[f].data[i] - onePass.faces[f].data[i]) > 1e-3f;
            covered += std::abs(onePass.faces[f].data[i] - backdrop.faces[f].data[i]) > 1e-3f;
        }
    EXPECT_GT(covered, total / 4); // the table fills about half the map
    // Only texels where two surfaces meet at equal depth may differ (the depth-only program
    // and the shaded one need not round depth alike): none on llvmpipe.
    EXPECT_LE(differing, total / 1000) << differing << " of " << total << " texel components differ";
}

// A phantom standing still relative to an object is shaded into a layer of its own once and
// reused as the backdrop of the object's map, drawn into depth alone on each update. The map
// must show the phantom, hide what is behind it, look the same with the layer as with the
// phantom shaded directly, and follow the phantom when it moves. The layer exists only for
// phantoms in their configured colour (a camera image would make it stale every frame).
TEST(EnvironmentProbes, PhantomLayerIsReusedUntilThePhantomMoves)
{
    RenderOptions options;
    options.environmentMaps.phantomsShowCamera = false;
    LUMAR_RENDERER_OR_SKIP(renderer, kWidth, kHeight, options);
    Scene scene = makeScene(renderer); // sphere (object 0) at x = -0.06, red lamp along its +x (object 1)
    GltfModel blueLamp = makeCube();
    blueLamp.materials[0] = test::emissiveMaterial({0.0f, 0.0f, 3.0f});
    GltfModel greenBox = makeCube();
    greenBox.materials[0] = test::emissiveMaterial({0.0f, 3.0f, 0.0f});
    // The blue lamp along the sphere's -x, hidden from it by the green phantom in between.
    scene.items.push_back({renderer.addModel(blueLamp), placed(-0.3, 0.0, 0.5, 0.08), 2});
    scene.items.push_back({renderer.addModel(greenBox), placed(-0.14, 0.0, 0.5, 0.06), -1, true});
    const Image8 background = test::solidImage(kWidth, kHeight, 0, 0, 0);
    const IblSettings settings;
    const auto sphereSees = [&] {
        renderer.render(background, intrinsics(), scene.items);
        EXPECT_NE(renderer.objectMaps(0), nullptr);
        return test::readMirrorMap(*renderer.objectMaps(0), settings.mirrorSize);
    };

    const CubeMapF first = sphereSees(); // the phantom shaded directly (not yet seen still)
    EXPECT_GT(maxOf(first.faces[1]).g, 2.5f);
    EXPECT_LT(maxOf(first.faces[1]).b, 0.5f); // the blue lamp stays hidden
    EXPECT_GT(maxOf(first.faces[0]).r, 2.5f);

    for (int frame = 0; frame < 2; ++frame) { // the layer drawn, then reused
        const CubeMapF still = sphereSees();
        for (size_t i = 0; i < first.faces[1].data.size(); ++i)
            ASSERT_NEAR(still.faces[1].data[i], first.faces[1].data[i], 1e-3f) << "frame " << frame << ", " << i;
        EXPECT_GT(maxOf(still.faces[0]).r, 2.5f); // the neighbours are drawn over the layer
    }

    // Moved above the sphere (camera -y; the environment frame is the camera's here): shaded
    // directly, then from a new layer.
    scene.items.back().cameraFromModel = placed(-0.06, -0.09, 0.5, 0.06);
    for (int frame = 0; frame < 2; ++frame) {
        const CubeMapF moved = sphereSees();
        EXPECT_LT(maxOf(moved.faces[1]).g, 0.5f) << frame;
        EXPECT_GT(maxOf(moved.faces[1]).b, 2.5f) << frame;
        EXPECT_GT(std::max(maxOf(moved.faces[2]).g, maxOf(moved.faces[3]).g), 2.5f) << frame;
    }
}

} // namespace
} // namespace lumar

namespace lumar {
namespace {

// SceneRenderer::forgetFrames(), which the pipeline calls after drawing a frame only to
// compile its programs: the frames after it are those of a renderer that drew none, maps
// (staggered every other frame here, so a map kept from before would show) and all.
TEST(EnvironmentProbes, AfterForgetFramesTheFramesAreAFreshRenderers)
{
    try {
        RenderOptions options;
        options.environmentMaps.policy = EnvironmentMapPolicy::EveryKFrames;
        options.environmentMaps.everyK = 2;
        auto used = SceneRenderer::create(kWidth, kHeight, options);
        auto fresh = SceneRenderer::create(kWidth, kHeight, options);
        const Scene before = makeScene(*used);
        const Scene after = makeScene(*fresh);
        // Elsewhere first: the lamp on the sphere's other side, both further away.
        Scene elsewhere = before;
        elsewhere.items[0].cameraFromModel = placed(0.06, 0.02, 0.6, 0.1);
        elsewhere.items[1].cameraFromModel = placed(-0.07, 0.0, 0.6, 0.08);
        const Image8 black = test::solidImage(kWidth, kHeight, 0, 0, 0);
        for (int i = 0; i < 3; ++i)
            used->render(black, intrinsics(), elsewhere.items);
        used->forgetFrames();
        for (int i = 0; i < 3; ++i) {
            Image8 a, b;
            used->render(black, intrinsics(), before.items);
            used->readback(a);
            fresh->render(black, intrinsics(), after.items);
            fresh->readback(b);
            EXPECT_EQ(used->lastStats().mapsUpdated, fresh->lastStats().mapsUpdated) << "frame " << i;
            EXPECT_EQ(a.data, b.data) << "frame " << i;
        }
    } catch (const RuntimeError& e) {
        GTEST_SKIP() << "no GLES 3 renderer: " << e.what();
    }
}

} // namespace
} // namespace lumar
