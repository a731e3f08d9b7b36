// EXT_meshopt_compression: buffer views whose data is stored compressed with meshoptimizer's
// codecs (attributes, triangles, indices) and filters (octahedral, quaternion, exponential).
// Internal to lumar_assets (gltf_compression.h).
#pragma once

#include <cstddef>

#include <tiny_gltf.h>

namespace lumar::gltf {

// Replaces each compressed buffer view's data by its decoded bytes (a new buffer per view)
// and removes the extension object; `bytesLeft` is the model's decoding budget
// (kMaxDecodedBytes), reduced by what is decoded. Throws InputError naming the buffer view.
void decodeMeshoptBufferViews(tinygltf::Model& model, size_t& bytesLeft);

} // namespace lumar::gltf
