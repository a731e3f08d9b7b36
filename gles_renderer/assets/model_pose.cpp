#include "gles_renderer/assets/model_pose.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <utility>

#include <glm/gtc/matrix_transform.hpp>

#include "core/error.h"
#include "gles_renderer/assets/gltf_animation.h"

namespace lumar {
namespace {

void growBounds(const glm::mat4& modelFromMesh, const glm::vec3& lo, const glm::vec3& hi, glm::vec3& boundsMin,
                glm::vec3& boundsMax)
{
    for (int corner = 0; corner < 8; ++corner) {
        const glm::vec3 local((corner & 1) ? hi.x : lo.x, (corner & 2) ? hi.y : lo.y, (corner & 4) ? hi.z : lo.z);
        const glm::vec3 p(modelFromMesh * glm::vec4(local, 1.0f));
        boundsMin = glm::min(boundsMin, p);
        boundsMax = glm::max(boundsMax, p);
    }
}

} // namespace

ModelPoser::ModelPoser(std::shared_ptr<const GltfRig> rig) : rig_(std::move(rig))
{
    nodes_.resize(rig_->nodes.size());
    modelFromNode_.resize(rig_->nodes.size());
    jointMatrices_.resize(rig_->skins.size());
    for (size_t s = 0; s < rig_->skins.size(); ++s)
        jointMatrices_[s].resize(rig_->skins[s].joints.size());
    modelFromMesh_.resize(rig_->primitives.size());
    posed_.resize(rig_->primitives.size());
    for (size_t p = 0; p < rig_->primitives.size(); ++p) {
        if (const auto& deformation = rig_->primitives[p].deformation) {
            posed_[p].positions = deformation->positions;
            posed_[p].normals = deformation->normals;
            posed_[p].tangents = deformation->tangents;
        }
    }
    pose({});
}

void ModelPoser::applyClip(const ClipTime& clip)
{
    if (clip.animation < 0 || size_t(clip.animation) >= rig_->animations.size())
        throw InputError("animation " + std::to_string(clip.animation) + " does not exist (the model has " +
                         std::to_string(rig_->animations.size()) + ")");
    const Animation& animation = rig_->animations[size_t(clip.animation)];
    const float seconds = float(clip.seconds);
    for (const AnimationChannel& channel : animation.channels) {
        const AnimationSampler& sampler = animation.samplers[size_t(channel.sampler)];
        NodePose& node = nodes_[size_t(channel.node)];
        sample_.resize(size_t(sampler.components));
        const bool rotation = channel.property == AnimatedProperty::Rotation;
        sampleAnimation(sampler, seconds, rotation, sample_);
        switch (channel.property) {
        case AnimatedProperty::Translation:
            node.translation = {sample_[0], sample_[1], sample_[2]};
            break;
        case AnimatedProperty::Rotation:
            node.rotation = glm::quat(sample_[3], sample_[0], sample_[1], sample_[2]);
            break;
        case AnimatedProperty::Scale:
            node.scale = {sample_[0], sample_[1], sample_[2]};
            break;
        case AnimatedProperty::Weights:
            node.weights.assign(sample_.begin(), sample_.end());
            break;
        }
    }
}

void ModelPoser::pose(std::span<const ClipTime> clips)
{
    const GltfRig& rig = *rig_;
    for (size_t n = 0; n < rig.nodes.size(); ++n) {
        const RigNode& rest = rig.nodes[n];
        nodes_[n].translation = rest.translation;
        nodes_[n].rotation = rest.rotation;
        nodes_[n].scale = rest.scale;
        nodes_[n].weights = rest.weights;
    }
    for (const ClipTime& clip : clips)
        applyClip(clip);
    for (const int n : rig.order) {
        const RigNode& rest = rig.nodes[size_t(n)];
        const NodePose& node = nodes_[size_t(n)];
        const glm::mat4 local = rest.matrix
                                    ? *rest.matrix
                                    : glm::translate(glm::mat4(1.0f), node.translation) *
                                          glm::mat4_cast(node.rotation) * glm::scale(glm::mat4(1.0f), node.scale);
        modelFromNode_[size_t(n)] = rest.parent >= 0 ? modelFromNode_[size_t(rest.parent)] * local : local;
    }
    // glTF 2.0 §3.7.3.3: joint matrix = the joint's global transform x its inverse bind matrix.
    for (size_t s = 0; s < rig.skins.size(); ++s)
        for (size_t j = 0; j < rig.skins[s].joints.size(); ++j)
            jointMatrices_[s][j] = modelFromNode_[size_t(rig.skins[s].joints[j])] * rig.skins[s].inverseBindMatrices[j];

    glm::vec3 lo(std::numeric_limits<float>::max()), hi(std::numeric_limits<float>::lowest());
    for (size_t p = 0; p < rig.primitives.size(); ++p) {
        const RiggedPrimitive& primitive = rig.primitives[p];
        if (primitive.deformation) {
            poseVertices(p);
            glm::vec3 meshLo(std::numeric_limits<float>::max()), meshHi(std::numeric_limits<float>::lowest());
            for (const glm::vec3& v : posed_[p].positions) {
                meshLo = glm::min(meshLo, v);
                meshHi = glm::max(meshHi, v);
            }
            growBounds(modelFromMesh_[p], meshLo, meshHi, lo, hi);
        } else {
            modelFromMesh_[p] = modelFromNode_[size_t(primitive.node)] * primitive.nodeFromMesh;
            growBounds(modelFromMesh_[p], primitive.meshBoundsMin, primitive.meshBoundsMax, lo, hi);
        }
    }
    // A wild animation (a scale keyed to infinity) leaves the bounds where they were.
    if (std::isfinite(lo.x + lo.y + lo.z + hi.x + hi.y + hi.z)) {
        boundsMin_ = lo;
        boundsMax_ = hi;
    }
}

void ModelPoser::poseVertices(size_t p)
{
    const RiggedPrimitive& primitive = rig_->primitives[p];
    const PrimitiveDeformation& d = *primitive.deformation;
    PosedVertices& out = posed_[p];
    const VertexArrays posed{out.positions, out.normals, out.tangents};
    ConstVertexArrays source{d.positions, d.normals, d.tangents};
    if (!d.targets.empty()) {
        applyMorphTargets(source, d.targets, nodes_[size_t(primitive.node)].weights, posed);
        source = {out.positions, out.normals, out.tangents};
    }
    if (primitive.skin >= 0) {
        // Skinned vertices land in model space: the mesh node's own transform does not apply
        // (glTF 2.0 §3.7.3.1).
        skinVertices(jointMatrices_[size_t(primitive.skin)], d.influences, source, posed);
        modelFromMesh_[p] = glm::mat4(1.0f);
    } else {
        if (d.targets.empty()) // neither: cannot happen (the reader keeps no deformation then)
            std::copy(d.positions.begin(), d.positions.end(), out.positions.begin());
        modelFromMesh_[p] = modelFromNode_[size_t(primitive.node)] * primitive.nodeFromMesh;
    }
}

void applyPose(const ModelPoser& poser, std::vector<GltfPrimitive>& primitives)
{
    for (size_t p = 0; p < primitives.size() && p < poser.rig().primitives.size(); ++p) {
        primitives[p].modelFromMesh = poser.modelFromMesh(p);
        if (poser.deforms(p)) {
            primitives[p].positions = poser.positions(p);
            primitives[p].normals = poser.normals(p);
            primitives[p].tangents = poser.tangents(p);
        }
    }
}

} // namespace lumar
