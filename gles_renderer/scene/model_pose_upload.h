// An animated model posed for a frame: its rig evaluated on the CPU (assets/model_pose.h), the
// transforms and bounds written into its GpuModel, and the vertices of skinned and morphed
// primitives uploaded into its vertex buffers (the model's and its stand-in's).
//
// Why the CPU and not a skinning vertex shader: every object is drawn 8 to 10 times a frame
// (into the other objects' six cube faces, the shadow map, phantom depth, the frame), and
// each of those draws would skin every vertex again, where posing once here serves them all
// with the existing shaders unchanged (no joint uniforms, no second vertex layout, no
// morph-target textures). On llvmpipe vertex shading runs on the same CPU anyway; on a
// GPU the upload is a few hundred kB a frame (CesiumMan: 3.3k vertices x 48 bytes, twice).
// `lumar bench` reports the cost as its "animation" stage.
#pragma once

#include <cstddef>
#include <memory>
#include <span>
#include <vector>

#include "gles_renderer/assets/gltf_model.h"
#include "gles_renderer/assets/model_pose.h"
#include "gles_renderer/scene/gpu_model.h"

namespace lumar {

struct GpuModelPose {
    explicit GpuModelPose(const GltfModel& model);
    ModelPoser poser;
    // Copies of the model's deforming primitives (uvs and all), whose posed vertices are
    // interleaved from them; empty for the others.
    std::vector<GltfPrimitive> staging;
    std::vector<std::byte> interleaved; // scratch
};

// The posing state for `model` (GltfModel::rig), null for a model without animations.
std::shared_ptr<GpuModelPose> makeGpuModelPose(const GltfModel& model);

// Poses `model` (which has a GpuModelPose) at `clips` and uploads the result. Throws
// InputError for an animation the model does not have.
void poseGpuModel(GpuModel& model, std::span<const ClipTime> clips);

} // namespace lumar
