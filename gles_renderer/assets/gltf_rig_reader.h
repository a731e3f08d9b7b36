// Reading a glTF file's rig (gltf_rig.h) from its tinygltf model, every index, count and
// keyframe time checked. Internal to lumar_assets: messages carry no file name, the loader
// adds it.
#pragma once

#include <memory>
#include <vector>

#include <tiny_gltf.h>

#include "gles_renderer/assets/gltf_model.h"
#include "gles_renderer/assets/gltf_rig.h"

namespace lumar::gltf {

// Whether anything in the file moves or deforms its meshes: animations, skins on mesh
// nodes, or morph targets.
bool hasRig(const tinygltf::Model& model);

// The rig of `primitives` (the loader's, each knowing its node and mesh primitive). Throws
// InputError for a skin whose joints are not nodes, a channel targeting a missing node, a
// sampler whose input and output counts disagree, keyframe times that do not increase,
// joint indices beyond the skin, and the like.
std::shared_ptr<GltfRig> readGltfRig(const tinygltf::Model& model, const std::vector<GltfPrimitive>& primitives);

} // namespace lumar::gltf
