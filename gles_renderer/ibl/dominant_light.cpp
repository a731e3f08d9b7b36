#include "gles_renderer/ibl/dominant_light.h"

#include <array>
#include <cmath>
#include <numbers>

namespace lumar {

DominantLight dominantLightFromSH9(const SH9& sh)
{
    // Band 1 is stored as (y, z, x) (environment_map.h).
    const glm::dvec3 luminance(0.2126, 0.7152, 0.0722);
    const glm::dvec3 linear(glm::dot(glm::dvec3(sh[3]), luminance), glm::dot(glm::dvec3(sh[1]), luminance),
                            glm::dot(glm::dvec3(sh[2]), luminance));
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
    light.color = glm::vec3(glm::max(numerator / denominator, glm::dvec3(0.0)));
    return light;
}

DominantLight dominantLight(const ImageF& equirect)
{
    return dominantLightFromSH9(projectEquirectSH9(equirect));
}

} // namespace lumar
