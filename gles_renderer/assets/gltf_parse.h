// Reading a .glb or .gltf file into a tinygltf model, with the checks tinygltf 2.7 leaves
// out done first (GLB chunk bounds, image buffer views inside their buffers, image sizes).
// Internal to lumar_assets: error messages carry no file name, the loader adds it.
#pragma once

#include <filesystem>

#include <tiny_gltf.h>

namespace lumar::gltf {

// Parses `file` (binary when it ends in .glb or starts with the GLB magic, JSON otherwise);
// external buffers and images are looked up beside it. Images are decoded by tinygltf (stb).
// tinygltf's warnings are logged; its first error line becomes the InputError's message.
tinygltf::Model parseGltfFile(const std::filesystem::path& file);

} // namespace lumar::gltf
