// Compressed glTF geometry: KHR_draco_mesh_compression (gltf_draco.h) and
// EXT_meshopt_compression (gltf_meshopt.h), decoded into plain buffers, buffer views and
// accessors before anything reads the model, so the accessor readers (gltf_accessors.h) and
// every feature after them see an uncompressed file.
// Internal to lumar_assets: error messages carry no file name, the loader adds it.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <tiny_gltf.h>

namespace lumar::gltf {

// All the decoded data of one model together: as much as the largest file the loader reads
// (gltf_parse.cpp), so a small file cannot decode into more memory than a large one holds.
inline constexpr size_t kMaxDecodedBytes = size_t(1) << 30;

// The two extensions' names as glTF files spell them.
inline constexpr const char* kDraco = "KHR_draco_mesh_compression";
inline constexpr const char* kMeshopt = "EXT_meshopt_compression";

// A GLB's little-endian 32-bit word at `p` (header and chunk fields).
inline uint32_t readLittleEndian32(const unsigned char* p)
{
    return uint32_t(p[0]) | uint32_t(p[1]) << 8 | uint32_t(p[2]) << 16 | uint32_t(p[3]) << 24;
}

// Whether this build decodes each extension (CMake options LUMAR_WITH_DRACO and
// LUMAR_WITH_MESHOPT_DECODER).
bool dracoDecoderBuilt();
bool meshoptDecoderBuilt();

// tinygltf 2.7 cannot read some valid compressed files as they are: it refuses a Draco
// primitive's index accessor, which has no bufferView, and it reads the placeholder
// ("fallback") buffer of a meshopt file, which has no data, from the GLB's binary chunk or
// from a uri it does not have. For a file that uses either extension this returns the JSON
// with those parts moved aside (the Draco indices into the extension object, each fallback
// buffer replaced by a one-byte placeholder); nothing when the JSON needs no change. A file
// that requires an extension this build cannot decode is refused here, naming it.
std::optional<std::string> prepareCompressedJson(std::string_view json, bool binary);

// A GLB (already checked: gltf_parse.cpp) with its JSON chunk replaced by `json`.
std::vector<unsigned char> glbWithJson(const std::vector<unsigned char>& glb, std::string_view json);

// A non-negative integer member of an extension object (tinygltf keeps JSON integers as int
// and larger ones as double); nothing when absent, InputError naming `what` when not such a
// number.
std::optional<size_t> countMember(const tinygltf::Value& object, const char* key, const std::string& what);

// Decodes every compressed buffer view and Draco primitive of `model` (parsed from the JSON
// prepareCompressedJson returned) and drops both extensions from extensionsRequired.
void decodeCompressedData(tinygltf::Model& model);

} // namespace lumar::gltf
