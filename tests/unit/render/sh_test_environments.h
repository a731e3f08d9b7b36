// The analytic environments of the SH projection tests and of tests/tools/sh_error_table,
// with their SH9 coefficients in closed form (Funk–Hecke: a radiance f(d·a) about an axis a
// has c_k = λ_l Y_k(a), λ_l = 2π ∫ f(t) P_l(t) dt, for any basis of band l; it holds for the
// rounded constants of shBasis too, as each Y_k is still a harmonic polynomial of degree l).
#pragma once

#include <array>
#include <cmath>
#include <numbers>
#include <string>

#include <glm/glm.hpp>

#include "gles_renderer/ibl/sh_projection.h"

namespace lumar::test {

struct ShEnvironment {
    std::string name;
    RadianceFunction radiance;
    SH9 closedForm;
};

// c_k = colour · λ_l(k) · Y_k(axis) for a zonal radiance colour · f(d·axis).
inline SH9 zonalSH9(const glm::vec3& axis, const glm::dvec3& colour, const std::array<double, 3>& lambda)
{
    constexpr std::array<int, 9> band = {0, 1, 1, 1, 2, 2, 2, 2, 2};
    const std::array<float, 9> y = shBasis(axis);
    SH9 sh;
    for (size_t k = 0; k < 9; ++k) {
        sh[k] = glm::vec3(colour * (lambda[size_t(band[k])] * double(y[k])));
    }
    return sh;
}

// λ_l of exp(κ(t − 1)): with I_n = ∫_{-1}^{1} t^n e^{κ(t−1)} dt, integration by parts gives
// I_n = (1 − (−1)^n e^{−2κ})/κ − (n/κ) I_{n−1}; P_0 = 1, P_1 = t, P_2 = (3t² − 1)/2.
inline std::array<double, 3> peakedLobeLambda(double kappa)
{
    const double e = std::exp(-2.0 * kappa);
    const double i0 = (1.0 - e) / kappa;
    const double i1 = (1.0 + e) / kappa - i0 / kappa;
    const double i2 = (1.0 - e) / kappa - 2.0 * i1 / kappa;
    constexpr double twoPi = 2.0 * std::numbers::pi;
    return {twoPi * i0, twoPi * i1, twoPi * (3.0 * i2 - i0) / 2.0};
}

// L = c, a coloured constant.
inline ShEnvironment constantEnvironment()
{
    const glm::dvec3 colour(1.0, 2.0, 0.5);
    return {"constant", [colour](glm::vec3) { return glm::vec3(colour); },
            zonalSH9(glm::vec3(0, 1, 0), colour, {4.0 * std::numbers::pi, 0.0, 0.0})};
}

// One bright direction: L = c · exp(κ(d·a − 1)), κ = 30 (half maximum at ~12° from a),
// a off every axis.
inline ShEnvironment peakedLobeEnvironment()
{
    constexpr double kappa = 30.0;
    // Normalised in double: with κ = 30 a float axis 1e-7 off unit length would scale L by
    // exp(30 · 1e-7), a 2e-6 error the quadratures would then measure.
    const glm::dvec3 axis = glm::normalize(glm::dvec3(0.3, 0.5, -0.8));
    const glm::dvec3 colour(3.0, 2.0, 1.0);
    return {"peaked lobe (kappa=30)",
            [=](glm::vec3 d) { return glm::vec3(colour * std::exp(kappa * (glm::dot(glm::dvec3(d), axis) - 1.0))); },
            zonalSH9(glm::vec3(axis), colour, peakedLobeLambda(kappa))};
}

// L = c · max(0, d·a): λ = π, 2π/3, π/4 (Ramamoorthi & Hanrahan's Â_l).
inline ShEnvironment cosineLobeEnvironment()
{
    constexpr double pi = std::numbers::pi;
    const glm::dvec3 axis = glm::normalize(glm::dvec3(-0.4, 0.7, 0.6));
    const glm::dvec3 colour(1.0, 0.8, 0.6);
    return {"cosine lobe",
            [=](glm::vec3 d) { return glm::vec3(colour * std::max(0.0, glm::dot(glm::dvec3(d), axis))); },
            zonalSH9(glm::vec3(axis), colour, {pi, 2.0 * pi / 3.0, pi / 4.0})};
}

} // namespace lumar::test
