// Per-vertex normals and tangents for meshes whose files do not supply them.
//
// Conventions are glTF's: uv (0,0) is the top-left of the image and v grows downwards;
// a tangent's xyz points along +u and its w is the handedness, so that the bitangent
// B = cross(N, T.xyz) * w points up the image (along -v), which is what tangent-space
// normal maps authored with MikkTSpace expect.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include <glm/glm.hpp>

namespace lumar {

// Area-weighted vertex normals: each triangle adds its unnormalised face normal (twice its
// area) to its three vertices, so vertices shared across faces get a smooth normal and
// unshared ones keep their face's flat normal. Vertices on no triangle (or only on
// degenerate ones) get +Z. `indices` holds whole triangles, each index < positions.size().
std::vector<glm::vec3> generateVertexNormals(std::span<const glm::vec3> positions, std::span<const uint32_t> indices);

// Tangents from the uv parametrisation: per triangle, the directions of +u and -v in
// space are accumulated per vertex weighted by the corner angle (as MikkTSpace does),
// then T is made orthogonal to N (Gram-Schmidt) and w = +1 or -1 tells whether
// cross(N, T) agrees with the accumulated -v direction. Where the uvs give no
// information (degenerate uv triangles) T is any unit vector orthogonal to N, w = +1.
// `normals` must be unit length.
std::vector<glm::vec4> generateTangents(std::span<const glm::vec3> positions, std::span<const glm::vec3> normals,
                                        std::span<const glm::vec2> uvs, std::span<const uint32_t> indices);

// The uv set generated tangents follow: the normal map's (glTF normalTexture.texCoord, with
// KHR_texture_transform's override), because its texels are authored in that set's tangent
// frame; TEXCOORD_0 where it names 0 or a set the primitive lacks (empty `uvs1`).
std::span<const glm::vec2> normalMapUvs(int normalTexCoord, std::span<const glm::vec2> uvs0,
                                        std::span<const glm::vec2> uvs1);

} // namespace lumar
