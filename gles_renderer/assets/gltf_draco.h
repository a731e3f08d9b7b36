// KHR_draco_mesh_compression: primitives whose attributes and indices are one Draco-encoded
// mesh (or point cloud) in a buffer view, decoded with Debian's libdraco.
// Internal to lumar_assets (gltf_compression.h).
#pragma once

#include <cstddef>

#include <tiny_gltf.h>

namespace lumar::gltf {

// Name of the extension object member the Draco primitive's index accessor is moved to
// before tinygltf reads the JSON (prepareCompressedJson).
inline constexpr const char* kDracoIndicesKey = "lumarIndices";

// Decodes each Draco primitive into new buffers, buffer views and accessors (the file's
// accessors describe the decoded data: type, component type, count), points the primitive
// at them and removes the extension object. `bytesLeft` as for meshopt. Throws InputError
// naming the mesh and primitive.
void decodeDracoPrimitives(tinygltf::Model& model, size_t& bytesLeft);

} // namespace lumar::gltf
