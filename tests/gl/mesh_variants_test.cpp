// MeshPass links one variant of mesh.frag per material for every view: the frame and the
// environment maps' cube faces share it, the uniform choosing the output (sRGB-encoded,
// tone-mapped codes in the frame; linear radiance in a face). Each linked program costs
// ~1 MB resident on llvmpipe, and the car scene's 9 materials once linked 18.
#include <algorithm>

#include <gtest/gtest.h>

#include "gl_readback.h"
#include "gl_test_support.h"
#include "gles_renderer/assets/builtin_shapes.h"
#include "gles_renderer/ibl/cube_face_camera.h"
#include "gles_renderer/ibl_gpu/ibl_pipeline.h"
#include "gles_renderer/scene/camera_projection.h"
#include "gles_renderer/scene/environment_probes.h"
#include "gles_renderer/scene/gpu_model.h"
#include "gles_renderer/scene/mesh_pass.h"

namespace lumar {
namespace {

constexpr int kSize = 32;
constexpr float kEmission = 3.0f;
constexpr float kExposure = 0.2f; // the frame's radiance 0.6: below the response's knee

GltfModel lamp()
{
    GltfModel model = makeCube();
    GltfMaterial& m = model.materials[0];
    m.baseColorFactor = glm::vec4(0, 0, 0, 1);
    m.emissiveFactor = glm::vec3(kEmission, 0.0f, 0.0f);
    return model;
}

TEST(MeshVariants, TheFrameAndTheCubeFacesShareOneProgramAndEachWritesItsOwnEncoding)
{
    LUMAR_RENDERER_OR_SKIP(renderer, kSize, kSize); // for its GL context
    (void)renderer;
    const DefaultTextures defaults = makeDefaultTextures();
    std::vector<GpuModel> gpu;
    gpu.push_back(uploadModel(lamp(), defaults));
    IblPipeline pipeline;
    IblMaps grey = pipeline.createMaps();
    pipeline.renderMirror(grey, nullptr, [](int) {
        glClearColor(0.0f, 0.0f, 0.0f, 1.0f);
        glClear(GL_COLOR_BUFFER_BIT);
    });
    pipeline.updateDerivedMaps(grey);
    const std::vector<const IblMaps*> lighting = {&grey};
    MeshPass meshes;

    // A cube face: the lamp 0.2 m ahead fills the middle of the +X face (the face camera
    // looks along +z of its own frame).
    const int faceSize = pipeline.settings().mirrorSize;
    IblMaps face = pipeline.createMaps();
    pipeline.renderMirror(face, nullptr, [&](int f) {
        glClearColor(0.0f, 0.0f, 0.0f, 1.0f);
        glClear(GL_COLOR_BUFFER_BIT);
        const glm::dmat4 faceFromCube(faceCameraFromCube(f));
        const DrawItem item{0, faceFromCube * test::translation(0.2, 0.0, 0.0) * glm::dmat4(glm::dmat3(0.1))};
        const FrameUniforms frame = cubeFaceFrameUniforms(f, faceSize, pipeline.rgbm());
        const DrawItem items[] = {item};
        meshes.draw(frame, gpu, items, lighting, -1, MeshPass::Phantoms::Shaded, MeshPass::Detail::Full, 0.0);
    });
    const CubeMapF seen = pipeline.rgbm() ? test::readCubeAtlasRgbm(face.mirror.name(), faceSize)
                                          : test::readCubeAtlas(face.mirror.name(), faceSize);
    const ImageF& plusX = seen.faces[0];
    const size_t centre = 3 * (size_t(faceSize / 2) * size_t(faceSize) + size_t(faceSize / 2));
    // Linear radiance, beyond what a tone-mapped code could hold.
    EXPECT_NEAR(plusX.data[centre], kEmission, 0.05f * kEmission);
    EXPECT_NEAR(plusX.data[centre + 1], 0.0f, 0.01f);

    // The frame: an RGBA8 target, the lamp 0.5 m ahead filling its middle.
    const test::FrameTarget target(kSize, kSize);
    ASSERT_TRUE(target.complete());
    const CameraIntrinsics intrinsics = test::makeIntrinsics(kSize, kSize, 40, 40, 15.5, 15.5);
    FrameUniforms frame;
    frame.clipFromCamera = glm::mat4(clipFromCamera(intrinsics, kSize, kSize));
    frame.frameParams = glm::vec4(1.0f, 0.0f, pipeline.rgbm() ? 1.0f : 0.0f, kExposure);
    const DrawItem items[] = {{0, test::translation(0.0, 0.0, 0.5) * glm::dmat4(glm::dmat3(0.1))}};
    meshes.draw(frame, gpu, items, lighting, -1, MeshPass::Phantoms::Shaded, MeshPass::Detail::Full, 0.0);
    uint8_t pixel[4] = {};
    glReadPixels(kSize / 2, kSize / 2, 1, 1, GL_RGBA, GL_UNSIGNED_BYTE, pixel);
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    // Tone-mapped and sRGB-encoded (linear 0.6 would be code 153).
    EXPECT_NEAR(int(pixel[0]), test::toneMappedCode(kExposure * kEmission), 2);
    EXPECT_EQ(int(pixel[1]), 0);

    // One material, two views: one program.
    EXPECT_EQ(meshes.linkedVariants(), 1U);
}

// A primitive without COLOR_0 or TEXCOORD_1 arrays gets a variant that reads the constants
// (white, (0, 0)) instead of interpolating them (mesh_feature::kVertexExtras): one material
// drawn on a primitive with vertex colours and on one without links two variants, and each
// shows what it should (unlit: the colour is the base colour times the vertex colour).
TEST(MeshVariants, APrimitiveWithoutVertexColoursReadsWhiteFromItsOwnVariant)
{
    LUMAR_RENDERER_OR_SKIP(renderer, kSize, kSize); // for its GL context
    (void)renderer;
    GltfMaterial unlit;
    unlit.unlit = true;
    GltfModel model = test::cameraFacingRectangle(-0.3f, -0.2f, -0.02f, 0.2f, unlit);
    model.primitives[0].colors.assign(4, glm::vec4(1.0f, 0.0f, 0.0f, 1.0f));
    model.primitives.push_back(test::cameraFacingRectangle(0.02f, -0.2f, 0.3f, 0.2f, unlit).primitives[0]);
    const DefaultTextures defaults = makeDefaultTextures();
    std::vector<GpuModel> gpu;
    gpu.push_back(uploadModel(model, defaults));
    IblPipeline pipeline;
    IblMaps maps = pipeline.createMaps();
    const std::vector<const IblMaps*> lighting = {&maps};

    const test::FrameTarget target(kSize, kSize);
    ASSERT_TRUE(target.complete());
    const CameraIntrinsics intrinsics = test::makeIntrinsics(kSize, kSize, 40, 40, 15.5, 15.5);
    FrameUniforms frame;
    frame.clipFromCamera = glm::mat4(clipFromCamera(intrinsics, kSize, kSize));
    frame.frameParams = glm::vec4(1.0f, 0.0f, pipeline.rgbm() ? 1.0f : 0.0f, 1.0f);
    MeshPass meshes;
    const DrawItem items[] = {{0, test::translation(0.0, 0.0, 1.0)}};
    meshes.draw(frame, gpu, items, lighting, -1, MeshPass::Phantoms::Shaded, MeshPass::Detail::Full, 0.0);
    // x = 15.5 + 40 x / z: the coloured rectangle's middle at column 9, the other's at 22.
    uint8_t left[4] = {}, right[4] = {};
    glReadPixels(9, kSize / 2, 1, 1, GL_RGBA, GL_UNSIGNED_BYTE, left);
    glReadPixels(22, kSize / 2, 1, 1, GL_RGBA, GL_UNSIGNED_BYTE, right);
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    EXPECT_EQ(glm::ivec3(left[0], left[1], left[2]), glm::ivec3(255, 0, 0));
    EXPECT_EQ(glm::ivec3(right[0], right[1], right[2]), glm::ivec3(255, 255, 255));
    EXPECT_EQ(meshes.linkedVariants(), 2U);
}

// The renderer releases the GLSL compiler after each frame (Mesa frees its built-in
// functions): a model loaded later whose material needs a variant not linked yet (a reload
// that adds it) still gets it compiled, and draws as it should.
TEST(MeshVariants, AVariantFirstNeededAfterTheCompilerWasReleasedStillRenders)
{
    LUMAR_RENDERER_OR_SKIP(renderer, kSize, kSize);
    renderer.setEnvironment(test::uniformEnvironment(0.0f), 1.0f); // emission alone lights
    const CameraIntrinsics intrinsics = test::makeIntrinsics(kSize, kSize, 40, 40, 15.5, 15.5);
    const auto centreAfterFrame = [&](const GltfMaterial& material) {
        renderer.removeModels();
        const DrawItem item{renderer.addModel(test::cameraFacingRectangle(-0.2f, -0.2f, 0.2f, 0.2f, material)),
                            test::translation(0, 0, 1)};
        renderer.render(test::solidImage(kSize, kSize, 0, 0, 0), intrinsics, {&item, 1});
        Image8 out;
        renderer.readback(out);
        const uint8_t* p = out.at(kSize / 2, kSize / 2);
        return glm::ivec3(p[0], p[1], p[2]);
    };
    GltfMaterial plain;
    plain.baseColorFactor = glm::vec4(0, 0, 0, 1);
    EXPECT_EQ(centreAfterFrame(plain), glm::ivec3(0));
    const GltfMaterial lamp = test::emissiveMaterial(glm::vec3(0.5f, 0.0f, 0.0f));
    const glm::ivec3 lit = centreAfterFrame(lamp);
    EXPECT_NEAR(lit.r, test::toneMappedCode(0.5), 2);
    EXPECT_EQ(lit.g, 0);
}

} // namespace
} // namespace lumar
