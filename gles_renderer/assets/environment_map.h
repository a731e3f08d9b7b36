// The real environment: an equirectangular Radiance .hdr map and its 9 spherical-harmonic
// coefficients (computed on the CPU for now).
//
// Direction convention (the same as ../shared/data/env and three.js): world +Y up; pixel
// (u, v) in [0,1]^2, v = 0 the top row, looks along
//   d = (sin(theta) cos(phi), cos(theta), sin(theta) sin(phi)), theta = v*pi, phi = (u-0.5)*2pi
// i.e. u = 0.5 + atan2(d.z, d.x) / (2 pi), v = acos(d.y) / pi.
#pragma once

#include <array>
#include <filesystem>

#include <glm/glm.hpp>

#include "core/image.h"

namespace lumar {

// Throws InputError "FILE: what is wrong" for a missing or corrupt file.
ImageF loadHdrImage(const std::filesystem::path& file);

using SH9 = std::array<glm::vec3, 9>;

// Real SH basis, bands 0..2, in the order (0,0) (1,-1) (1,0) (1,1) (2,-2) (2,-1) (2,0) (2,1) (2,2)
// with y, z, x for band 1 (the order of sh9_reference.json).
std::array<float, 9> shBasis(const glm::vec3& unitDirection);

// Projection of an equirectangular map with each pixel weighted by its exact solid angle.
SH9 projectEquirectSH9(const ImageF& equirect);

// Irradiance E(n) from SH coefficients (Ramamoorthi & Hanrahan 2001).
glm::vec3 irradianceSH9(const SH9& sh, const glm::vec3& unitNormal);

} // namespace lumar
