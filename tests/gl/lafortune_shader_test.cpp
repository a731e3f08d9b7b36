// shaders_es/lafortune.glsl, as mesh.frag runs it, against its CPU twin
// (gles_renderer/ibl/lafortune_shading.h) over a grid of view directions and parameters: the
// lobe's peak direction and magnitude, the Fresnel factor, the glossiness that selects the
// maps and the weight of the map lookup, with and without the tangent rotation. Phong lobes
// (C = -1, -1, 1) go through phongShade, the shortcut without a tangent frame.
#include <cmath>
#include <cstdio>
#include <optional>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "core/error.h"
#include "embedded_shaders.h"
#include "gl_readback.h"
#include "gles_renderer/gl/egl_context.h"
#include "gles_renderer/gl/gl_check.h"
#include "gles_renderer/ibl/lafortune_shading.h"
#include "test_shader.h"

namespace lumar {
namespace {

struct Case {
    glm::vec3 v, n, t, lobe, rhoS;
    float exponent, phi, rotation;
};

constexpr int kColumns = 64;
constexpr int kInputRows = 5; // texels per case, stacked vertically

const char* kMain = R"(
uniform sampler2D uCases;
layout(location = 0) out vec4 outDirection; // xyz lobe direction, w magnitude
layout(location = 1) out vec4 outWeight;    // xyz specular weight, w glossiness
layout(location = 2) out vec4 outFresnel;   // x Fresnel factor, yzw the rotated tangent
void main()
{
    ivec2 cell = ivec2(gl_FragCoord.xy);
    vec4 a = texelFetch(uCases, ivec2(cell.x, cell.y * 5 + 0), 0);
    vec4 b = texelFetch(uCases, ivec2(cell.x, cell.y * 5 + 1), 0);
    vec4 c = texelFetch(uCases, ivec2(cell.x, cell.y * 5 + 2), 0);
    vec4 d = texelFetch(uCases, ivec2(cell.x, cell.y * 5 + 3), 0);
    vec4 e = texelFetch(uCases, ivec2(cell.x, cell.y * 5 + 4), 0);
    vec3 n = b.xyz;
    vec3 t = rotateTangent(c.xyz, n, c.w);
    vec3 bitangent = cross(n, t);
    // Phong lobes through phongShade, as mesh.frag's PHONG_LOBE variants run them: the same
    // CPU reference holds for both.
    LafortuneShade s = d.xyz == vec3(-1.0, -1.0, 1.0) ? phongShade(a.xyz, n, a.w, e.xyz, b.w)
                                                      : lafortuneShade(a.xyz, t, bitangent, n, d.xyz, a.w, e.xyz, b.w);
    outDirection = vec4(s.lobeDirection, s.magnitude);
    outWeight = vec4(s.specularWeight, s.glossiness);
    outFresnel = vec4(s.fresnel, t);
}
)";

std::vector<Case> makeCases()
{
    std::vector<Case> cases;
    const glm::vec3 n(0.0f, 0.0f, 1.0f), t(1.0f, 0.0f, 0.0f);
    const glm::vec3 lobes[] = {
        {-1.0f, -1.0f, 1.0f}, {-1.0f, -0.8f, 1.0f}, {-0.9f, -0.5f, 0.95f}, {-1.1f, -1.1f, 1.05f}};
    const float exponents[] = {1.0f, 8.0f, 64.0f, 500.0f, 4096.0f};
    const float phis[] = {0.0f, 1.0f / 6.0f, 0.5f};
    const float rotations[] = {0.0f, 0.3f, 0.75f};
    const glm::vec3 rhos[] = {glm::vec3(0.04f), glm::vec3(0.9f, 0.5f, 0.2f)};
    for (int elevation = 0; elevation < 6; ++elevation)
        for (int azimuth = 0; azimuth < 6; ++azimuth) {
            // From the normal to grazing (cos 0.05), round the normal.
            const float cosTheta = 1.0f - 0.95f * float(elevation) / 5.0f;
            const float sinTheta = std::sqrt(1.0f - cosTheta * cosTheta);
            const float phi = 2.0f * 3.14159265f * (float(azimuth) + 0.25f) / 6.0f;
            const glm::vec3 v(sinTheta * std::cos(phi), sinTheta * std::sin(phi), cosTheta);
            for (const glm::vec3& lobe : lobes)
                for (const float exponent : exponents)
                    for (const float fresnelPhi : phis)
                        for (const float rotation : rotations)
                            for (const glm::vec3& rho : rhos)
                                cases.push_back({v, n, t, lobe, rho, exponent, fresnelPhi, rotation});
        }
    return cases;
}

TEST(LafortuneShader, MatchesTheCpuEvaluationOverAGridOfDirectionsAndParameters)
{
    LUMAR_CONTEXT_OR_SKIP(context);
    const std::vector<Case> cases = makeCases();
    const int rows = int((cases.size() + kColumns - 1) / kColumns);

    std::vector<float> input(size_t(kColumns) * size_t(rows) * kInputRows * 4, 0.0f);
    for (size_t i = 0; i < cases.size(); ++i) {
        const Case& c = cases[i];
        const size_t x = i % kColumns, y = i / kColumns;
        const glm::vec4 texels[kInputRows] = {
            {c.v, c.exponent}, {c.n, c.phi}, {c.t, c.rotation}, {c.lobe, 0.0f}, {c.rhoS, 0.0f}};
        for (size_t k = 0; k < kInputRows; ++k)
            for (size_t j = 0; j < 4; ++j)
                input[((y * kInputRows + k) * kColumns + x) * 4 + j] = texels[k][int(j)];
    }
    GlTexture casesTexture = GlTexture::create();
    glBindTexture(GL_TEXTURE_2D, casesTexture.name());
    glTexStorage2D(GL_TEXTURE_2D, 1, GL_RGBA32F, kColumns, rows * kInputRows);
    glTexSubImage2D(GL_TEXTURE_2D, 0, 0, 0, kColumns, rows * kInputRows, GL_RGBA, GL_FLOAT, input.data());

    const std::string fragment = "#version 300 es\nprecision highp float;\nprecision highp sampler2D;\n" +
                                 std::string(shaders::source("lafortune.glsl")) + kMain;
    const GlProgram program = test::linkFullscreenTestProgram(fragment);

    GlTexture outputs[3];
    GlFramebuffer framebuffer = GlFramebuffer::create();
    glBindFramebuffer(GL_FRAMEBUFFER, framebuffer.name());
    for (int k = 0; k < 3; ++k) {
        outputs[k] = GlTexture::create();
        glBindTexture(GL_TEXTURE_2D, outputs[k].name());
        glTexStorage2D(GL_TEXTURE_2D, 1, GL_RGBA32F, kColumns, rows);
        glFramebufferTexture2D(GL_FRAMEBUFFER, GLenum(GL_COLOR_ATTACHMENT0 + k), GL_TEXTURE_2D, outputs[k].name(), 0);
    }
    const GLenum buffers[3] = {GL_COLOR_ATTACHMENT0, GL_COLOR_ATTACHMENT1, GL_COLOR_ATTACHMENT2};
    glDrawBuffers(3, buffers);
    checkFramebufferComplete("the BRDF probe target");
    glViewport(0, 0, kColumns, rows);
    glUseProgram(program.name());
    glActiveTexture(GL_TEXTURE0);
    glBindTexture(GL_TEXTURE_2D, casesTexture.name());
    glUniform1i(glGetUniformLocation(program.name(), "uCases"), 0);
    GlVertexArray vertexArray = GlVertexArray::create();
    glBindVertexArray(vertexArray.name());
    glDrawArrays(GL_TRIANGLES, 0, 3);
    checkGlError("drawing the BRDF probe");

    std::vector<std::vector<float>> read(3, std::vector<float>(size_t(kColumns) * size_t(rows) * 4));
    for (int k = 0; k < 3; ++k) {
        glReadBuffer(GLenum(GL_COLOR_ATTACHMENT0 + k));
        glReadPixels(0, 0, kColumns, rows, GL_RGBA, GL_FLOAT, read[size_t(k)].data());
    }

    float worstDirection = 0, worstMagnitude = 0, worstWeight = 0, worstGloss = 0, worstFresnel = 0;
    for (size_t i = 0; i < cases.size(); ++i) {
        const Case& c = cases[i];
        const glm::vec3 t = rotateTangent(c.t, c.n, c.rotation);
        const LafortuneShade cpu = lafortuneShade(c.v, t, glm::cross(c.n, t), c.n, c.lobe, c.exponent, c.rhoS, c.phi);
        const float* d = &read[0][i * 4];
        const float* w = &read[1][i * 4];
        const float* f = &read[2][i * 4];
        // Relative to the value's scale (magnitudes span many orders with n up to 4096).
        const auto relative = [](float gpu, float ref) { return std::abs(gpu - ref) / std::max(1e-3f, std::abs(ref)); };
        worstDirection = std::max(worstDirection, glm::length(glm::vec3(d[0], d[1], d[2]) - cpu.lobeDirection));
        worstMagnitude = std::max(worstMagnitude, relative(d[3], cpu.magnitude));
        for (int k = 0; k < 3; ++k)
            worstWeight = std::max(worstWeight, relative(w[k], cpu.specularWeight[k]));
        worstGloss = std::max(worstGloss, std::abs(w[3] - cpu.glossiness));
        worstFresnel = std::max(worstFresnel, std::abs(f[0] - cpu.fresnel));
        ASSERT_LT(glm::length(glm::vec3(f[1], f[2], f[3]) - t), 1e-5f) << "case " << i;
    }
    std::printf("%zu cases: worst |dir| %.2e, magnitude %.2e (rel), weight %.2e (rel), glossiness %.2e, Fresnel %.2e\n",
                cases.size(), worstDirection, worstMagnitude, worstWeight, worstGloss, worstFresnel);
    EXPECT_LT(worstDirection, 1e-5f);
    EXPECT_LT(worstMagnitude, 1e-3f); // exp2/log2 of n up to 4096 in single precision: 2.8e-4 measured
    EXPECT_LT(worstWeight, 1e-3f);
    EXPECT_LT(worstGloss, 1e-5f);
    EXPECT_LT(worstFresnel, 1e-5f);
}

} // namespace
} // namespace lumar
