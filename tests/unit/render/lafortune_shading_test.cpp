// Properties of the paper's shading model on the CPU twin of lafortune.glsl (the GL test
// holds the shader to this code): the Phong special case, the tangent rotation turning the
// whole anisotropic lobe about the normal, and the Fresnel factor acting only near grazing.
#include <cmath>
#include <cstdio>
#include <numbers>

#include <glm/gtc/matrix_transform.hpp>
#include <gtest/gtest.h>

#include "gles_renderer/ibl/lafortune_shading.h"

namespace lumar {
namespace {

const glm::vec3 kN(0, 0, 1), kT(1, 0, 0), kB(0, 1, 0);

glm::vec3 viewAt(float cosTheta, float azimuth)
{
    const float s = std::sqrt(1.0f - cosTheta * cosTheta);
    return {s * std::cos(azimuth), s * std::sin(azimuth), cosTheta};
}

glm::vec3 turnAboutNormal(const glm::vec3& v, float angle)
{
    return glm::vec3(glm::rotate(glm::mat4(1.0f), angle, kN) * glm::vec4(v, 0.0f));
}

TEST(LafortuneShading, PhongLobePeaksAtTheMirrorDirectionWithUnitMagnitude)
{
    for (float c = 0.1f; c <= 1.0f; c += 0.1f)
        for (float a = 0.0f; a < 6.28f; a += 0.7f) {
            const glm::vec3 v = viewAt(c, a);
            const LafortuneShade s = lafortuneShade(v, kT, kB, kN, {-1, -1, 1}, 64.0f, glm::vec3(0.5f), 0.0f);
            const glm::vec3 mirror = 2.0f * glm::dot(v, kN) * kN - v;
            EXPECT_LT(glm::length(s.lobeDirection - mirror), 1e-5f);
            EXPECT_NEAR(s.magnitude, 1.0f, 1e-4f);
            EXPECT_NEAR(s.glossiness, 0.5f, 1e-6f);           // log2(64) / 12
            EXPECT_NEAR(s.specularWeight.x, 0.5f * c, 1e-4f); // rho_s x falloff (n.r = n.v)
        }
}

// Rotating the tangent by a*pi turns the whole lobe by a*pi about the normal: shading a
// view v with the rotated frame equals shading the view turned back by a*pi with the
// original frame, and turning the resulting lobe forward again.
TEST(LafortuneShading, TangentRotationTurnsTheAnisotropicLobeByTheEncodedAngle)
{
    const glm::vec3 lobe(-1.0f, -0.6f, 0.9f); // strongly anisotropic
    for (const float a : {0.1f, 0.25f, 0.5f, 0.8f}) {
        const float angle = a * std::numbers::pi_v<float>;
        const glm::vec3 t = rotateTangent(kT, kN, a);
        EXPECT_NEAR(glm::dot(t, kT), std::cos(angle), 1e-6f);
        for (float c = 0.2f; c <= 1.0f; c += 0.2f)
            for (float az = 0.0f; az < 6.28f; az += 0.9f) {
                const glm::vec3 v = viewAt(c, az);
                const LafortuneShade turned = lafortuneShade(v, t, glm::cross(kN, t), kN, lobe, 40.0f, glm::vec3(1), 0);
                const LafortuneShade plain =
                    lafortuneShade(turnAboutNormal(v, -angle), kT, kB, kN, lobe, 40.0f, glm::vec3(1), 0);
                EXPECT_LT(glm::length(turned.lobeDirection - turnAboutNormal(plain.lobeDirection, angle)), 1e-5f);
                EXPECT_NEAR(turned.magnitude, plain.magnitude, 1e-5f * std::max(1.0f, plain.magnitude));
            }
    }
    // And the anisotropy is real: the same elevation seen along T and along B differs.
    const float alongT = lafortuneShade(viewAt(0.5f, 0.0f), kT, kB, kN, lobe, 40.0f, glm::vec3(1), 0).magnitude;
    const float alongB = lafortuneShade(viewAt(0.5f, 1.5708f), kT, kB, kN, lobe, 40.0f, glm::vec3(1), 0).magnitude;
    EXPECT_GT(alongT / alongB, 10.0f);
}

// f(R) = (1 - R.N)^(1/phi - 1): phi -> 0 switches it off. Off and on (phi = 1/6) differ by
// under 3 % of rho_s' while n.v > 0.5 ((1 - 0.5)^5 = 0.03), and at grazing the reflection
// rises towards a mirror: the measured gain is printed.
TEST(LafortuneShading, FresnelActsOnlyNearGrazingAngles)
{
    const glm::vec3 rho(0.04f);
    for (float c = 0.5f; c <= 1.0f; c += 0.05f) {
        const LafortuneShade off = lafortuneShade(viewAt(c, 0.3f), kT, kB, kN, {-1, -1, 1}, 64.0f, rho, 0.0f);
        const LafortuneShade on = lafortuneShade(viewAt(c, 0.3f), kT, kB, kN, {-1, -1, 1}, 64.0f, rho, 1.0f / 6.0f);
        EXPECT_LE(on.fresnel, 0.0313f);
        // rho_s gains at most 0.96 f and the falloff at most (1 - c) f: under 0.035 of c here.
        EXPECT_LT((on.specularWeight.x - off.specularWeight.x) / c, 0.035f);
        EXPECT_GE(on.specularWeight.x, off.specularWeight.x);
    }
    const LafortuneShade off = lafortuneShade(viewAt(0.05f, 0.3f), kT, kB, kN, {-1, -1, 1}, 64.0f, rho, 0.0f);
    const LafortuneShade on = lafortuneShade(viewAt(0.05f, 0.3f), kT, kB, kN, {-1, -1, 1}, 64.0f, rho, 1.0f / 6.0f);
    const float gain = on.specularWeight.x / off.specularWeight.x;
    std::printf("grazing (n.v = 0.05) gain of the specular weight with phi = 1/6: %.1fx (rho_s %.3f -> %.3f, "
                "falloff %.3f -> %.3f, glossiness %.3f -> %.3f)\n",
                gain, 0.04, 0.04 + 0.96 * on.fresnel, 0.05, 0.05 + 0.95 * on.fresnel, off.glossiness, on.glossiness);
    EXPECT_GT(gain, 100.0f);
    EXPECT_GT(on.glossiness, 0.85f); // pushed towards the mirror map
    // phi = 0.5 is linear in (1 - R.N).
    const LafortuneShade linear = lafortuneShade(viewAt(0.3f, 0.3f), kT, kB, kN, {-1, -1, 1}, 64.0f, rho, 0.5f);
    EXPECT_NEAR(linear.fresnel, 0.7f, 1e-5f);
}

TEST(LafortuneShading, GlossyBlendIsContinuousAcrossTheFourMaps)
{
    // The blended map position 4s (below 1/2) and 2 + 2(s - 1/2)... expressed as a single
    // coordinate must be continuous and monotone in s.
    const auto position = [](float s) {
        const glm::vec2 b = glossyBlend(s);
        return b.x + b.y;
    };
    float last = position(0.0f);
    for (float s = 0.001f; s <= 1.0f; s += 0.001f) {
        const float p = position(s);
        EXPECT_GE(p, last - 1e-6f);
        EXPECT_LT(p - last, 0.01f);
        last = p;
    }
    EXPECT_NEAR(position(1.0f), 3.0f, 1e-6f);
}

} // namespace
} // namespace lumar
