// CPU cube maps: 6 linear float faces addressed exactly as OpenGL ES 3.0 addresses a
// TEXTURE_CUBE_MAP, so CPU references and GPU read-backs agree texel for texel.
//
// Face order +X −X +Y −Y +Z −Z (GL_TEXTURE_CUBE_MAP_POSITIVE_X + face). Face selection is the
// ES 3.0 spec's table (§3.8.10, "Cube Map Texture Selection"): the major axis ma picks the
// face, then
//   +X: sc = −rz, tc = −ry     −X: sc = +rz, tc = −ry
//   +Y: sc = +rx, tc = +rz     −Y: sc = +rx, tc = −rz
//   +Z: sc = +rx, tc = −ry     −Z: sc = −rx, tc = −ry
//   s = (sc/|ma| + 1)/2,  t = (tc/|ma| + 1)/2.
// Texel (x, y) of a face covers s ∈ [x, x+1]/size, t ∈ [y, y+1]/size: column 0 is s near 0,
// row 0 is t near 0 (the first row glTexImage2D uploads). ImageF's "row 0 at the top" is
// therefore just "row 0 = t near 0" here. Where two coordinates tie for the major axis the
// spec lets the implementation choose; we take the first of x, y, z.
#pragma once

#include <array>
#include <functional>

#include <glm/glm.hpp>

#include "core/image.h"

namespace lumar {

// Largest face side accepted (6·4096²·12 bytes ≈ 1.2 GB).
constexpr int kMaxCubeSize = 4096;

struct CubeMapF {
    int size = 0;
    std::array<ImageF, 6> faces; // size×size, 3 channels, linear radiance
};

struct CubeCoord {
    int face = 0; // 0..5 = +X −X +Y −Y +Z −Z
    float s = 0;  // [0, 1] across the face
    float t = 0;
};

// The unit direction through face coordinates (s, t) of `face`. Throws InputError for a
// face outside 0..5.
glm::vec3 cubeTexelDirection(int face, float s, float t);

// The direction through the centre of texel (x, y) of a face of side `size`.
glm::vec3 cubeTexelCentreDirection(int face, int size, int x, int y);

// Throws InputError unless 1 ≤ size ≤ kMaxCubeSize and every face is size×size×3.
void checkCubeMap(const CubeMapF& cube);

// The largest channel value of any texel (0 for an empty map): the scale map errors are
// stated as a share of.
float maxComponent(const CubeMapF& cube);

// Face and (s, t) that GL would sample for `dir` (need not be unit). Throws InputError for
// a zero or non-finite direction.
CubeCoord cubeCoordinate(const glm::vec3& dir);

// Bilinear filtering within the selected face, clamped at its edges (no filtering across
// faces, unlike seamless GL sampling: the difference is confined to the outer half texel).
glm::vec3 sampleCubeBilinear(const CubeMapF& cube, const glm::vec3& dir);

// The texel that contains (s, t).
glm::vec3 sampleCubeNearest(const CubeMapF& cube, const glm::vec3& dir);

// A cube whose every texel holds radiance(direction through the texel centre). Throws
// InputError unless 1 ≤ size ≤ kMaxCubeSize.
CubeMapF cubeFromFunction(int size, const std::function<glm::vec3(glm::vec3)>& radiance);

// Bilinear lookup of a 3-channel equirectangular map in the direction convention of
// environment_map.h, wrapping in longitude and clamping at the poles.
glm::vec3 sampleEquirectBilinear(const ImageF& equirect, const glm::vec3& dir);

// A cube resampled from an equirectangular map (sampleEquirectBilinear at texel centres).
// Throws InputError for an empty or non-3-channel map or a bad size.
CubeMapF cubeFromEquirect(const ImageF& equirect, int size);

// The exact solid angle of texel (x, y) on a face of side `size` (the same for all faces).
double texelSolidAngleExact(int size, int x, int y);

// King's approximation: dω ≈ Δu·Δv / (u² + v² + 1)^{3/2}, u, v ∈ [−1, 1] at the texel centre,
// Δu = Δv = 2/size, i.e. 4 / (size² (u² + v² + 1)^{3/2}). (DESIGN.md writes it as
// 4/(u² + v² + 1)^{3/2} · ΔuΔv with Δu, Δv measured in [0, 1] face coordinates, 1/size.)
double texelSolidAngleKing(int size, int x, int y);

} // namespace lumar
