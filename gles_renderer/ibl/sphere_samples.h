// Fixed direction sets for the paper's SH projection (DESIGN.md §6.2): directions spread
// uniformly over the sphere, each of equal weight 4π/N, so that
//   c_lm ≈ (4π / N) Σ_k L(ω_k) Y_lm(ω_k)
// works for any map format through a plain lookup of L. Also equal-solid-angle samples of
// a cone (cap) around +Z for prefiltering glossy maps with a Phong lobe.
//
// Sphere convention (the one of environment_map.h): +Y up, polar angle θ measured from +Y,
// azimuth φ measured from +X towards +Z:  d = (sinθ cosφ, cosθ, sinθ sinφ).
//
// Determinism: the jitter comes from std::mt19937, whose output sequence the C++ standard
// fixes; floats are built from the raw 32-bit words here (std::uniform_real_distribution
// is implementation-defined), so a seed gives the same directions on every platform
// (up to the last ulp of libm's sin/cos/sqrt).
#pragma once

#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

namespace lumar {

// Largest grid side accepted (4096² ≈ 16.8 M directions, 200 MB): a guard against a typo
// in a config, far beyond any useful sample count.
constexpr int kMaxSampleGridSide = 4096;

// gridSide² directions, one per cell of a jittered gridSide×gridSide grid in (x, y) ∈ [0,1)²
// mapped with θ = 2·acos(√(1 − x)) (so cosθ = 1 − 2x is uniform in [-1, 1]) and φ = 2π·y.
// Index k = j·gridSide + i for cell column i (x) and row j (y); cell (i, j) draws its jitter
// ξx then ξy from std::mt19937(seed). Throws InputError unless 1 ≤ gridSide ≤ 4096.
std::vector<glm::vec3> stratifiedSphereSamples(int gridSide, uint32_t seed);

// The spherical Fibonacci set: cosθ_k = 1 − (2k + 1)/count, φ_k = k · π(3 − √5) (the golden
// angle), with θ about +Y as above. Throws InputError unless 1 ≤ count ≤ 4096².
std::vector<glm::vec3> fibonacciSphereSamples(int count);

// gridSide² directions in the cap around +Z of half-angle acos(cosMaxAngle), uniform in
// solid angle: cosθ = 1 − x(1 − cosMaxAngle), φ = 2π·y from a jittered grid as above, with θ
// measured from +Z here: d = (sinθ cosφ, sinθ sinφ, cosθ). Each direction stands for
// capSolidAngle(cosMaxAngle) / gridSide². Throws InputError unless 1 ≤ gridSide ≤ 4096
// and -1 ≤ cosMaxAngle < 1.
std::vector<glm::vec3> stratifiedCapSamples(int gridSide, float cosMaxAngle, uint32_t seed);

// The Fibonacci spiral restricted to the same cap: cosθ_k = 1 − (k + ½)(1 − cosMaxAngle)/count,
// φ_k = k · golden angle, θ from +Z; equal solid angle per direction, more evenly spread than
// a jittered grid (no clumps), which matters when a small bright source falls in the cap.
// Throws InputError unless 1 ≤ count ≤ 4096² and -1 ≤ cosMaxAngle < 1.
std::vector<glm::vec3> fibonacciCapSamples(int count, float cosMaxAngle);

// count directions around +Z with density proportional to cos^m θ within the cap
// cosθ ≥ cosMaxAngle (importance sampling of a Phong lobe, m its exponent, or of a broader
// one): the Fibonacci spiral in the warped domain, u_k = (k + ½)/count,
// cosθ_k^(m+1) = 1 − u_k (1 − cosMaxAngle^(m+1)) (the inverse of the CDF over the cap),
// φ_k = k · golden angle, θ from +Z. Each direction stands for 1/count of the density, so
// its own solid angle is 1/(count · powerCapPdf(cosθ_k)): small at the centre, large in the
// tails. Index order runs from the centre out; m = 0 gives fibonacciCapSamples. Throws
// InputError unless 1 ≤ count ≤ 4096², m ≥ 0 and 0 ≤ cosMaxAngle < 1.
std::vector<glm::vec3> powerCapSamples(int count, float exponent, float cosMaxAngle);

// That density over solid angle at cosθ: (m + 1) cos^m θ / (2π (1 − cosMaxAngle^(m+1))) in
// the cap, 0 outside it.
double powerCapPdf(double cosTheta, double exponent, double cosMaxAngle);

// The solid angle 2π(1 − cosMaxAngle) of that cap.
double capSolidAngle(float cosMaxAngle);

} // namespace lumar
