// shaders_es/shadow.glsl's kernel across a straight shadow edge: the four corners of a 3 x 3
// grid, which the virtual objects (mesh.frag) and the real surfaces (phantom_receiver.frag)
// both take since issue 18, against the whole 3 x 3 grid (what the receivers took before), the
// reference, written out below. The four corners must reach as far as the nine taps and stay
// within 1/6 of them: their penumbra climbs in two steps of 1/2 where the nine's climbs in
// three of 1/3. A single bilinear tap (a penumbra one texel wide) would be 1/3 off one texel
// from the edge, and fails.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "embedded_shaders.h"
#include "gles_renderer/gl/gl_check.h"
#include "gles_renderer/gl/gpu_texture.h"
#include "test_shader.h"

namespace lumar {
namespace {

constexpr int kMapSize = 64;    // texels per side; the edge lies between texels 31 and 32
constexpr int kSamples = 512;   // positions across the edge, 8 texels wide in all
constexpr float kSpan = 8.0f;   // texels
constexpr float kRadius = 1.5f; // shadowParams.x: the renderer's default softness
constexpr float kOccluder = 0.25f, kReference = 0.5f, kFar = 1.0f;

const char* kMain = R"(
uniform vec3 uProbe; // x samples, y their span in texels, z the reference depth
layout(location = 0) out vec4 outVisibility; // x four taps, y nine taps
// The reference: every tap of the 3 x 3 grid the corners belong to, averaged.
float nineTaps(vec4 coordinates)
{
    vec2 spacing = vec2(shadowParams.x * shadowParams.y);
    float sum = 0.0;
    for (int j = -1; j <= 1; ++j)
        for (int i = -1; i <= 1; ++i)
            sum += texture(uShadowMap, vec3(coordinates.xy + vec2(float(i), float(j)) * spacing, coordinates.z));
    return sum / 9.0;
}
void main()
{
    // Across the edge at u = 0.5, uProbe.y texels centred on it, in the middle row.
    float texels = (gl_FragCoord.x / uProbe.x - 0.5) * uProbe.y;
    vec4 coordinates = vec4(0.5 + texels * shadowParams.y, 0.5, uProbe.z, 1.0);
    outVisibility = vec4(shadowVisibilityFourTapsAt(coordinates),
                         nineTaps(coordinates), 0.0, 1.0);
}
)";

TEST(ShadowKernel, TheObjectsFourTapsReachAsFarAsTheNineAndStayWithinASixthOfThem)
{
    LUMAR_CONTEXT_OR_SKIP(context);
    // The occluder (depth 0.25) left of the edge, nothing (1) right of it; the reference 0.5.
    std::vector<uint32_t> depths(size_t(kMapSize) * kMapSize);
    for (int y = 0; y < kMapSize; ++y)
        for (int x = 0; x < kMapSize; ++x)
            depths[size_t(y) * kMapSize + size_t(x)] =
                uint32_t(double(x < kMapSize / 2 ? kOccluder : kFar) * 4294967295.0);
    glActiveTexture(GL_TEXTURE0);
    // The shadow map's own sampling (ShadowPass): linear, compared with GL_LEQUAL.
    const GlTexture map = makeDepthCompareTexture(kMapSize, kMapSize, false);
    glTexSubImage2D(GL_TEXTURE_2D, 0, 0, 0, kMapSize, kMapSize, GL_DEPTH_COMPONENT, GL_UNSIGNED_INT, depths.data());

    // shadow.glsl reads the light's members of the Frame block: plain uniforms here.
    const std::string fragment =
        "#version 300 es\nprecision highp float;\nprecision highp sampler2DShadow;\n"
        "uniform mat4 lightClipFromCamera;\nuniform vec4 shadowParams;\nuniform sampler2DShadow uShadowMap;\n" +
        std::string(shaders::source("shadow.glsl")) + kMain;
    const GlProgram program = test::linkFullscreenTestProgram(fragment);
    ASSERT_FALSE(::testing::Test::HasFailure());

    GlTexture output = GlTexture::create();
    glBindTexture(GL_TEXTURE_2D, output.name());
    glTexStorage2D(GL_TEXTURE_2D, 1, GL_RGBA32F, kSamples, 1);
    GlFramebuffer framebuffer = GlFramebuffer::create();
    glBindFramebuffer(GL_FRAMEBUFFER, framebuffer.name());
    glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, output.name(), 0);
    checkFramebufferComplete("the shadow kernel probe");
    glViewport(0, 0, kSamples, 1);
    glUseProgram(program.name());
    glBindTexture(GL_TEXTURE_2D, map.name());
    glUniform1i(glGetUniformLocation(program.name(), "uShadowMap"), 0);
    glUniform3f(glGetUniformLocation(program.name(), "uProbe"), float(kSamples), kSpan, kReference);
    glUniform4f(glGetUniformLocation(program.name(), "shadowParams"), kRadius, 1.0f / float(kMapSize), 0.0f, 0.0f);
    GlVertexArray vertexArray = GlVertexArray::create();
    glBindVertexArray(vertexArray.name());
    glDrawArrays(GL_TRIANGLES, 0, 3);
    checkGlError("drawing the shadow kernel probe");
    std::vector<float> read(size_t(kSamples) * 4);
    glReadPixels(0, 0, kSamples, 1, GL_RGBA, GL_FLOAT, read.data());

    // The penumbra: where a kernel is neither 0 nor 1, in texels from the edge.
    const auto texelsAt = [](int i) { return ((float(i) + 0.5f) / float(kSamples) - 0.5f) * kSpan; };
    float worst = 0.0f;
    float fourFrom = 1e9f, fourTo = -1e9f, nineFrom = 1e9f, nineTo = -1e9f;
    float previous = 0.0f;
    for (int i = 0; i < kSamples; ++i) {
        const float four = read[size_t(i) * 4], nine = read[size_t(i) * 4 + 1];
        worst = std::max(worst, std::abs(four - nine));
        EXPECT_GE(four, previous - 1e-4f) << "not monotonic at " << texelsAt(i) << " texels";
        previous = four;
        if (four > 1e-3f && four < 1.0f - 1e-3f) {
            fourFrom = std::min(fourFrom, texelsAt(i));
            fourTo = std::max(fourTo, texelsAt(i));
        }
        if (nine > 1e-3f && nine < 1.0f - 1e-3f) {
            nineFrom = std::min(nineFrom, texelsAt(i));
            nineTo = std::max(nineTo, texelsAt(i));
        }
    }
    std::printf("penumbra: four taps %.2f..%.2f, nine %.2f..%.2f texels; worst |four - nine| %.3f\n", fourFrom, fourTo,
                nineFrom, nineTo, worst);
    // Both climb from 0 to 1 over 2 r + 1 = 4 texels about the edge (a sample is 1/64 texel).
    const float step = kSpan / float(kSamples);
    EXPECT_NEAR(nineFrom, -(kRadius + 0.5f), 2.0f * step);
    EXPECT_NEAR(nineTo, kRadius + 0.5f, 2.0f * step);
    EXPECT_NEAR(fourFrom, nineFrom, 2.0f * step);
    EXPECT_NEAR(fourTo, nineTo, 2.0f * step);
    EXPECT_LE(worst, 1.0f / 6.0f + 0.01f);
    EXPECT_FLOAT_EQ(read[0], 0.0f);
    EXPECT_FLOAT_EQ(read[size_t(kSamples - 1) * 4], 1.0f);
}

} // namespace
} // namespace lumar
