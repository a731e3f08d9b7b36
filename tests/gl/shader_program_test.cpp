// Every embedded shader compiles on the real driver and every program links.
#include <optional>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "core/error.h"
#include "embedded_shaders.h"
#include "gles_renderer/gl/egl_context.h"
#include "gles_renderer/gl/shader_program.h"
#include "gles_renderer/scene/mesh_features.h"

namespace lumar {
namespace {

class Shaders : public ::testing::Test {
protected:
    void SetUp() override
    {
        try {
            context_.emplace(EglDisplay::surfaceless());
        } catch (const RuntimeError& e) {
            GTEST_SKIP() << e.what();
        }
    }
    std::optional<EglContext> context_;
};

TEST_F(Shaders, EveryEmbeddedShaderCompiles)
{
    ASSERT_GE(shaders::all().size(), 4u);
    for (const shaders::Entry& entry : shaders::all()) {
        SCOPED_TRACE(std::string(entry.name));
        // .glsl pieces are not stages: they are compiled inside the stages that include them.
        if (entry.name.ends_with(".glsl"))
            continue;
        EXPECT_NO_THROW(compileShader(entry.name));
    }
}

TEST_F(Shaders, EveryProgramTheRendererUsesLinks)
{
    for (const ProgramSources& program : kAllPrograms) {
        SCOPED_TRACE(std::string(program.vertex) + " + " + std::string(program.fragment));
        GlProgram linked;
        EXPECT_NO_THROW(linked = linkProgram(program));
        EXPECT_TRUE(linked);
    }
}

TEST_F(Shaders, MissingShaderIsARuntimeErrorNamingIt)
{
    try {
        compileShader("no_such_shader.frag");
        FAIL() << "expected RuntimeError";
    } catch (const RuntimeError& e) {
        EXPECT_NE(std::string(e.what()).find("no_such_shader.frag"), std::string::npos) << e.what();
    }
    EXPECT_THROW(linkProgram({"fullscreen.vert", "missing.frag"}), RuntimeError);
}

TEST_F(Shaders, ProgramWithoutARequestedUniformIsARuntimeError)
{
    const GlProgram program = linkProgram(kBackgroundProgram);
    EXPECT_THROW(uniformLocation(program, "uNoSuchUniform"), RuntimeError);
    EXPECT_THROW(bindUniformBlock(program, "NoSuchBlock", 0), RuntimeError);
}

TEST_F(Shaders, DefinesGoAfterTheVersionLine)
{
    // A define the source then uses: without it in the source, the program would compile.
    EXPECT_THROW(linkProgram(kMeshProgram, "#define HAS_SHADOW no_such_identifier\n"), RuntimeError);
    EXPECT_NO_THROW(linkProgram(kMeshProgram, ""));
}

TEST_F(Shaders, MeshVariantsLinkAndCompileOutWhatTheirMaterialLacks)
{
    using namespace mesh_feature;
    // Every lit feature at once (unlit materials skip the lighting: checked below).
    const uint32_t all = kBaseColorTexture | kSecondTexture | kLobeTexture | kRotationTexture | kLafortune |
                         kNormalMap | kEmission | kShadow | kRgbmMaps | kOcclusionTexture | kAlphaMask | kAlphaBlend |
                         kDiffuse | kTangentRotation | kPhongLobe;
    std::vector<uint32_t> masks = {0U, all};
    for (uint32_t bit = 1; (bit & all) != 0; bit <<= 1)
        masks.push_back(bit);
    for (const uint32_t mask : masks) {
        SCOPED_TRACE("features " + std::to_string(mask));
        GlProgram program;
        ASSERT_NO_THROW(program = linkProgram(kMeshProgram, meshVariantDefines(mask)));
        // The samplers a variant reads are exactly those its features need.
        EXPECT_EQ(optionalUniformLocation(program, "uBaseColor") >= 0, (mask & kBaseColorTexture) != 0);
        EXPECT_EQ(optionalUniformLocation(program, "uNormal") >= 0, (mask & kNormalMap) != 0);
        EXPECT_EQ(optionalUniformLocation(program, "uEmissive") >= 0, (mask & kEmission) != 0);
        // The shadow darkens the diffuse term only: without one, no shadow map is read.
        EXPECT_EQ(optionalUniformLocation(program, "uShadowMap") >= 0, (mask & kShadow) != 0 && (mask & kDiffuse) != 0);
        EXPECT_EQ(optionalUniformLocation(program, "uLobe") >= 0,
                  (mask & kLobeTexture) != 0 && (mask & kLafortune) != 0);
        EXPECT_EQ(optionalUniformLocation(program, "uOcclusion") >= 0, (mask & kOcclusionTexture) != 0);
        EXPECT_GE(optionalUniformLocation(program, "uMirrorMap"), 0);
    }
    // An unlit material reads its base colour alone: no environment map is left in it.
    GlProgram unlit;
    ASSERT_NO_THROW(unlit = linkProgram(kMeshProgram, meshVariantDefines(kUnlit | kBaseColorTexture)));
    EXPECT_GE(optionalUniformLocation(unlit, "uBaseColor"), 0);
    EXPECT_LT(optionalUniformLocation(unlit, "uMirrorMap"), 0);
}

// The reflectance bits: rho_d is the base colour factor times the rest, so a factor of 0
// (metals, glass) has no diffuse term whatever its texture; the tangent turns where the
// Lafortune rotation factor is not 0; the lobe is Phong's for metallic-roughness and for
// Lafortune lobes C = (-1, -1, 1) without a lobe texture.
TEST(MeshVariantDefines, TheReflectanceBitsFollowTheMaterialsFactors)
{
    MaterialUniforms chrome;
    chrome.baseColorFactor = glm::vec4(0.0f, 0.0f, 0.0f, 1.0f);
    chrome.metallicRoughness.z = 1.0f; // Lafortune
    chrome.lobeFactor = glm::vec4(-1.0f, -1.0f, 1.0f, 4096.0f);
    EXPECT_EQ(reflectanceFeatures(chrome), mesh_feature::kPhongLobe);
    MaterialUniforms paint = chrome;
    paint.baseColorFactor = glm::vec4(0.0f, 0.0f, 1e-6f, 1.0f);
    EXPECT_EQ(reflectanceFeatures(paint), mesh_feature::kDiffuse | mesh_feature::kPhongLobe);
    MaterialUniforms grille = chrome;
    grille.specularFactor.w = 1.0f;
    grille.lobeFactor = glm::vec4(-1.0f, -0.8f, 1.0f, 200.0f);
    EXPECT_EQ(reflectanceFeatures(grille), mesh_feature::kTangentRotation);
    MaterialUniforms textured = chrome;
    textured.textureFlags.z = 1.0f; // a lobe texture may change C anywhere
    EXPECT_EQ(reflectanceFeatures(textured), 0U);
    // Metallic-roughness has no tangent rotation, whatever the (unused) members hold, and
    // always a Phong lobe.
    MaterialUniforms metal = grille;
    metal.metallicRoughness.z = 0.0f;
    EXPECT_EQ(reflectanceFeatures(metal), mesh_feature::kPhongLobe);
    const std::string defines = meshVariantDefines(mesh_feature::kShadow);
    EXPECT_NE(defines.find("#define HAS_DIFFUSE false\n"), std::string::npos) << defines;
    EXPECT_NE(defines.find("#define HAS_TANGENT_ROTATION false\n"), std::string::npos) << defines;
}

TEST(MeshVariantDefines, FixEveryFeatureOnce)
{
    const std::string defines = meshVariantDefines(mesh_feature::kShadow);
    EXPECT_NE(defines.find("#define HAS_SHADOW true\n"), std::string::npos) << defines;
    EXPECT_NE(defines.find("#define HAS_BASE_COLOR_TEXTURE false\n"), std::string::npos) << defines;
    EXPECT_NE(defines.find("#define ALPHA_MODE 0.0\n"), std::string::npos) << defines;
    EXPECT_NE(meshVariantDefines(mesh_feature::kAlphaMask).find("#define ALPHA_MODE 1.0\n"), std::string::npos);
    size_t lines = 0;
    for (const char c : defines)
        lines += c == '\n' ? 1 : 0;
    EXPECT_EQ(lines, 17U); // sixteen features and the alpha mode
    EXPECT_NE(defines.find("#define HAS_VERTEX_EXTRAS false\n"), std::string::npos) << defines;
    EXPECT_NE(meshVariantDefines(mesh_feature::kVertexExtras).find("#define HAS_VERTEX_EXTRAS true\n"),
              std::string::npos);
    // The output's encoding is left to the uniform: the frame and the cube faces share a
    // variant (mesh_features.h).
    EXPECT_EQ(defines.find("WRITES_RADIANCE"), std::string::npos) << defines;
}

} // namespace
} // namespace lumar
