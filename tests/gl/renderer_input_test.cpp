// Bad input to the renderer is an InputError with a one-line message, never a crash.
#include <gtest/gtest.h>

#include "gl_test_support.h"

namespace lumar {
namespace {

constexpr int kWidth = 64, kHeight = 48;

template <typename F> std::string inputErrorOf(F&& f)
{
    try {
        f();
    } catch (const InputError& e) {
        return e.what();
    }
    return "(no InputError)";
}

GltfModel validQuad()
{
    return test::cameraFacingRectangle(-0.1f, -0.1f, 0.1f, 0.1f, test::emissiveMaterial({1, 1, 1}));
}

TEST(RendererInput, RejectsMalformedModelsNamingTheFile)
{
    LUMAR_RENDERER_OR_SKIP(renderer, kWidth, kHeight);
    GltfModel model = validQuad();
    model.file = "broken.glb";
    model.primitives[0].normals.pop_back();
    std::string message = inputErrorOf([&] { renderer.addModel(model); });
    EXPECT_EQ(message.rfind("broken.glb: primitive 0:", 0), 0u) << message;

    model = validQuad();
    model.primitives[0].indices[4] = 4;
    EXPECT_NE(inputErrorOf([&] { renderer.addModel(model); }).find("index 4 beyond 4 vertices"), std::string::npos);

    model = validQuad();
    model.primitives[0].indices.pop_back();
    EXPECT_NE(inputErrorOf([&] { renderer.addModel(model); }).find("whole number of triangles"), std::string::npos);

    model = validQuad();
    model.primitives[0].material = 3;
    EXPECT_NE(inputErrorOf([&] { renderer.addModel(model); }).find("material 3"), std::string::npos);

    model = validQuad();
    model.materials[0].normalTexture = 0; // no textures at all
    EXPECT_NE(inputErrorOf([&] { renderer.addModel(model); }).find("refers to texture 0"), std::string::npos);

    model = validQuad();
    model.textures.push_back({Image8(4, 4, 3), false});
    model.materials[0].baseColorTexture = 0;
    EXPECT_NE(inputErrorOf([&] { renderer.addModel(model); }).find("texture 0 is 4x4x3"), std::string::npos);
}

TEST(RendererInput, RejectsAMismatchedFrameOrUnknownModel)
{
    LUMAR_RENDERER_OR_SKIP(renderer, kWidth, kHeight);
    const CameraIntrinsics k = defaultIntrinsics(kWidth, kHeight);
    const Image8 background(kWidth, kHeight, 3);
    EXPECT_NE(inputErrorOf([&] { renderer.render(Image8(kWidth, kHeight - 1, 3), k, {}); }).find("background image"),
              std::string::npos);
    EXPECT_NE(inputErrorOf([&] {
                  renderer.render(background, defaultIntrinsics(kWidth * 2, kHeight), {});
              }).find("camera intrinsics"),
              std::string::npos);
    const DrawItem unknown{0, glm::dmat4(1.0)};
    EXPECT_NE(inputErrorOf([&] { renderer.render(background, k, {&unknown, 1}); }).find("model 0"), std::string::npos);
    // And the renderer still works afterwards.
    Image8 out;
    renderer.render(background, k, {});
    renderer.readback(out);
    EXPECT_EQ(out.data, background.data);
}

TEST(RendererInput, RejectsBadEnvironments)
{
    LUMAR_RENDERER_OR_SKIP(renderer, kWidth, kHeight);
    EXPECT_THROW(renderer.setEnvironment(ImageF(), 1.0f), InputError);
    EXPECT_THROW(renderer.setEnvironment(ImageF(8, 4, 4), 1.0f), InputError);
    EXPECT_THROW(renderer.setEnvironment(test::uniformEnvironment(1.0f), -1.0f), InputError);
    EXPECT_THROW(renderer.setEnvironment(test::uniformEnvironment(1.0f), std::nanf("")), InputError);
}

TEST(RendererInput, ModelWithoutMaterialsOrPrimitivesIsAccepted)
{
    LUMAR_RENDERER_OR_SKIP(renderer, kWidth, kHeight);
    GltfModel model = validQuad();
    model.materials.clear();
    model.primitives[0].material = -1; // glTF's default material
    EXPECT_NO_THROW(renderer.addModel(model));
    EXPECT_NO_THROW(renderer.addModel(GltfModel{}));
}

} // namespace
} // namespace lumar
