// Defensive reading of glTF accessors (tinygltf model underneath). Every offset, stride,
// count and index read from the file is checked against the buffers actually present, so a
// corrupt or hostile file ends in an InputError, never in a read outside a buffer.
// Internal to lumar_assets: the messages carry no file name, the loader adds it.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include <tiny_gltf.h>

namespace lumar::gltf {

// Upper bound on the elements of one accessor: far beyond any model we render, small enough
// that a lying count cannot make us allocate gigabytes.
inline constexpr size_t kMaxAccessorElements = size_t(1) << 24;

// Accessor `accessorIndex` as `components` floats per element, sparse substitution applied.
// FLOAT components are always accepted; with `allowNormalizedIntegers`, normalized unsigned
// byte/short components too (glTF's quantised texture coordinates), mapped to [0, 1].
// Non-finite values are rejected.
std::vector<float> readFloatAccessor(const tinygltf::Model& model, int accessorIndex, int components,
                                     bool allowNormalizedIntegers);

// KHR_mesh_quantization (positions, normals, tangents, texture coordinates, instance
// transforms): FLOAT, or signed/unsigned byte/short components, normalized or not.
std::vector<float> readQuantizedAccessor(const tinygltf::Model& model, int accessorIndex, int components);

// The number of components per element of accessor `accessorIndex` (1 for SCALAR, 3 for
// VEC3...), 0 when it does not exist or its type is unknown.
int accessorComponents(const tinygltf::Model& model, int accessorIndex);

// An index accessor: SCALAR of unsigned byte, short or int.
std::vector<uint32_t> readIndexAccessor(const tinygltf::Model& model, int accessorIndex);

// Accessor `accessorIndex` as `components` floats per element whatever its component type:
// normalized integers mapped as glTF 2.0 §3.11 says (signed ones to [-1, 1]), others as their
// values (exact up to 2^24). The caller checks the component types its use allows. Sparse
// substitution applied, non-finite values rejected. (Animation data: gltf_rig_reader.cpp.)
std::vector<float> readAccessorAsFloats(const tinygltf::Model& model, int accessorIndex, int components);

} // namespace lumar::gltf
