#include "gles_renderer/ibl/lafortune_shading.h"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace lumar {

glm::vec3 rotateTangent(const glm::vec3& t, const glm::vec3& n, float a)
{
    const float angle = a * std::numbers::pi_v<float>;
    return t * std::cos(angle) + glm::cross(n, t) * std::sin(angle);
}

LafortuneShade lafortuneShade(const glm::vec3& v, const glm::vec3& t, const glm::vec3& b, const glm::vec3& n,
                              const glm::vec3& lobe, float exponent, const glm::vec3& rhoS, float phi)
{
    const glm::vec3 peak = lobe * glm::vec3(glm::dot(v, t), glm::dot(v, b), glm::dot(v, n));
    const float len = glm::length(peak);
    LafortuneShade s;
    s.lobeDirection = len > 1e-8f ? (t * peak.x + b * peak.y + n * peak.z) / len : n;
    // Clamped in the log domain as the shader does: |C| > 1 with a large n would overflow.
    s.magnitude = len > 1e-8f ? std::exp2(std::min(exponent * std::log2(len), 4.0f)) : 0.0f;
    const float cosine = std::clamp(glm::dot(s.lobeDirection, n), 0.0f, 1.0f);
    s.fresnel = phi >= 1e-3f ? std::pow(1.0f - cosine, 1.0f / phi - 1.0f) : 0.0f;
    const float gloss = std::clamp(std::log2(std::max(exponent, 1.0f)) / kLog2MirrorExponent, 0.0f, 1.0f);
    s.glossiness = gloss + (1.0f - gloss) * s.fresnel;
    const glm::vec3 rhoSPrime = rhoS + (glm::vec3(1.0f) - rhoS) * s.fresnel;
    const float falloff = cosine + (1.0f - cosine) * s.fresnel;
    s.specularWeight = rhoSPrime * s.magnitude * falloff;
    return s;
}

glm::vec2 glossyBlend(float s)
{
    if (s < 0.25f)
        return {0.0f, s * 4.0f};
    if (s < 0.5f)
        return {1.0f, (s - 0.25f) * 4.0f};
    return {2.0f, std::min((s - 0.5f) * 2.0f, 1.0f)};
}

} // namespace lumar
