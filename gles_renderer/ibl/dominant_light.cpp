#include "gles_renderer/ibl/dominant_light.h"

#include <array>
#include <cmath>
#include <numbers>

namespace lumar {
namespace {

constexpr glm::dvec3 kLuminance(0.2126, 0.7152, 0.0722); // Rec. 709

} // namespace

DominantLight dominantLightFromSH9(const SH9& sh)
{
    // Band 1 is stored as (y, z, x) (environment_map.h).
    const glm::dvec3 linear(glm::dot(glm::dvec3(sh[3]), kLuminance), glm::dot(glm::dvec3(sh[1]), kLuminance),
                            glm::dot(glm::dvec3(sh[2]), kLuminance));
    const double length = glm::length(linear);
    DominantLight light;
    if (!(length > 0.0) || !std::isfinite(length))
        return light;
    const glm::dvec3 d = linear / length;

    // The light's irradiance SH is c·A_l·Y_lm(d), the environment's A_l·L_lm (A_l: the
    // clamped-cosine kernel, Ramamoorthi & Hanrahan 2001), so over bands 1 and 2
    //   c = Σ A_l² L_lm Y_lm(d) / Σ A_l² Y_lm(d)².
    constexpr double pi = std::numbers::pi;
    constexpr std::array<double, 9> kernel = {pi,     2 * pi / 3, 2 * pi / 3, 2 * pi / 3, pi / 4,
                                              pi / 4, pi / 4,     pi / 4,     pi / 4};
    const std::array<float, 9> y = shBasis(glm::vec3(d));
    glm::dvec3 numerator(0.0);
    double denominator = 0.0;
    for (size_t k = 1; k < 9; ++k) {
        const double weight = kernel[k] * kernel[k] * double(y[k]);
        numerator += weight * glm::dvec3(sh[k]);
        denominator += weight * double(y[k]);
    }
    light.direction = glm::vec3(d);
    glm::dvec3 colour = glm::max(numerator / denominator, glm::dvec3(0.0));
    // The fit gives the light all of the environment's anisotropy, a sky brighter than the
    // ground included; capped, the rest of the sky keeps its share (see the header).
    const double facing = glm::dot(glm::dvec3(irradianceSH9(sh, glm::vec3(d))), kLuminance);
    const double share = facing > 0.0 ? glm::dot(colour, kLuminance) / facing : 0.0;
    if (share > kMaxDominantLightShare)
        colour *= kMaxDominantLightShare / share;
    light.color = glm::vec3(colour);
    return light;
}

DominantLight dominantLight(const ImageF& equirect)
{
    return dominantLightFromSH9(projectEquirectSH9(equirect));
}

} // namespace lumar
