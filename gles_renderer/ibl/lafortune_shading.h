// The CPU twin of shaders_es/lafortune.glsl (DESIGN.md §6.4): the same formulas, so tests
// can hold the shader to a reference and tools can reason about materials without GL.
// McAllister's one-lobe Lafortune SBRDF looked up in prefiltered maps: the lobe's peak
// direction r = normalize(world(C o v_local)) and magnitude |C o v_local|^n, the falloff
// g = clamp(N.r), and the paper's Fresnel factor f(R) = (1 - R.N)^(1/phi - 1) that pushes
// rho_s, g and the normalised glossiness s towards a mirror at grazing angles.
#pragma once

#include <glm/glm.hpp>

namespace lumar {

// log2 of the mirror map's exponent: glossiness s = log2(n) / this, so the four maps sit at
// s = 0 (diffuse, n = 1), 1/4 (n = 8), 1/2 (n = 64) and 1 (the mirror, n = 4096).
inline constexpr float kLog2MirrorExponent = 12.0f;

struct LafortuneShade {
    glm::vec3 lobeDirection{0.0f}; // unit, in the frame t, b, n are given in
    float magnitude = 0.0f;
    float fresnel = 0.0f;
    float glossiness = 0.0f;
    glm::vec3 specularWeight{0.0f}; // rho_s' * magnitude * g'
};

// The tangent turned about the normal by a * pi.
glm::vec3 rotateTangent(const glm::vec3& t, const glm::vec3& n, float a);

// v: unit direction to the viewer; t, b, n: orthonormal local frame; lobe: C_x, C_y, C_z;
// exponent >= 1; rhoS: specular albedo; phi in [0, 1) (below 1e-3: no Fresnel).
LafortuneShade lafortuneShade(const glm::vec3& v, const glm::vec3& t, const glm::vec3& b, const glm::vec3& n,
                              const glm::vec3& lobe, float exponent, const glm::vec3& rhoS, float phi);

// The two maps glossiness s falls between (0: diffuse/glossy-1, 1: glossy-1/glossy-2,
// 2: glossy-2/mirror) and the weight of the second.
glm::vec2 glossyBlend(float s);

} // namespace lumar
