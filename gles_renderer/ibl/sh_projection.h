// CPU projections of radiance to nine SH coefficients (the SH9 type and shBasis() of
// environment_map.h): the paper's uniform-sample method (DESIGN.md §6.2), King's
// per-texel cube walk as the baseline, and brute-force references the tests and the
// GPU passes are checked against. Also the brute-force Phong-lobe prefilter (§6.3).
#pragma once

#include <functional>
#include <span>

#include <glm/glm.hpp>

#include "gles_renderer/assets/environment_map.h"
#include "gles_renderer/ibl/cube_map.h"

namespace lumar {

using RadianceFunction = std::function<glm::vec3(glm::vec3)>;

// The paper's estimator: (4π / N) Σ_k L(ω_k) Y(ω_k), with the sum in double. The directions
// must be unit and uniform over the sphere (sphere_samples.h). Throws InputError for none.
SH9 projectSH9Uniform(std::span<const glm::vec3> directions, const RadianceFunction& radiance);

// King (GPU Gems 2, ch. 10): every texel weighted by texelSolidAngleKing. The weights are NOT
// renormalised to sum to 4π: that is the classic method, and its weight error (the sum is
// 4π·(1 + 0.38 %) at size 8, falling as 1/size², see cube_map_test) is part of what the
// comparison with the uniform samples measures. (Renormalising, as D3DX's SHProjectCubeMap
// does, would hide that error for the constant term only.)
SH9 projectCubeSH9King(const CubeMapF& cube);

// Reference quadrature of a function: Gauss–Legendre in cosθ (θ from +Y) with thetaSteps
// nodes times 2·thetaSteps midpoint steps in φ, summed in double. Exact to rounding for
// band-limited radiance of degree < thetaSteps; for a radiance with kinks (a clamped lobe,
// a bilinear map) the error falls as ~1/thetaSteps². Throws InputError unless
// 1 ≤ thetaSteps ≤ 8192.
SH9 projectSH9BruteForce(const RadianceFunction& radiance, int thetaSteps);

// The cube's own content as piecewise-constant texels: every texel weighted by its exact
// solid angle (texelSolidAngleExact), with Y at the texel centre.
SH9 projectCubeSH9BruteForce(const CubeMapF& cube);

// The normalised Phong-lobe convolution at `direction`,
//   (n + 1)/(2π) ∫ L(ω) max(0, r·ω)^n dω,
// summed over every texel with its exact solid angle and divided by the same sum of the
// lobe alone, so a constant map gives exactly the constant. For n = 1 this is E(r)/π, the
// diffuse map. Throws InputError for a zero direction or a negative or non-finite exponent.
glm::vec3 prefilterPhongBruteForce(const CubeMapF& cube, const glm::vec3& direction, float exponent);

// The error measure of the SH tests and tools: max over the 27 numbers |c − c_ref|, divided
// by the largest |c_ref| of the 27 (0 when the reference is all zero and c equals it).
double sh9RelativeError(const SH9& sh, const SH9& reference);

} // namespace lumar
