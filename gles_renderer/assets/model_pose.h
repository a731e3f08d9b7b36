// A rigged model posed at a moment of its animations (glTF 2.0 §3.5, §3.7.3, §3.11): node
// transforms from the rest pose and the animation channels, joint matrices, morph weights,
// and every deforming primitive's vertices skinned and morphed on the CPU.
#pragma once

#include <memory>
#include <span>
#include <vector>

#include <glm/glm.hpp>
#include <glm/gtc/quaternion.hpp>

#include "gles_renderer/assets/gltf_model.h"
#include "gles_renderer/assets/gltf_rig.h"

namespace lumar {

// One animation of a rig at a time into it (seconds from its start: clipSeconds()).
struct ClipTime {
    int animation = 0;
    double seconds = 0.0;
};

class ModelPoser {
public:
    explicit ModelPoser(std::shared_ptr<const GltfRig> rig);

    // Poses the rig with `clips` applied over the rest pose, in order (a later clip's channel
    // overrides an earlier one's on the same property); no clips: the rest pose. Throws
    // InputError for an animation the rig does not have.
    void pose(std::span<const ClipTime> clips);

    [[nodiscard]] const GltfRig& rig() const { return *rig_; }
    // After pose(), per primitive of the model: where its vertices go (identity for a
    // skinned one, whose vertices are posed in model space) ...
    [[nodiscard]] const glm::mat4& modelFromMesh(size_t primitive) const { return modelFromMesh_[primitive]; }
    // ... whether it deforms, and then its posed vertices.
    [[nodiscard]] bool deforms(size_t primitive) const { return rig_->primitives[primitive].deformation != nullptr; }
    [[nodiscard]] const std::vector<glm::vec3>& positions(size_t primitive) const
    {
        return posed_[primitive].positions;
    }
    [[nodiscard]] const std::vector<glm::vec3>& normals(size_t primitive) const { return posed_[primitive].normals; }
    [[nodiscard]] const std::vector<glm::vec4>& tangents(size_t primitive) const { return posed_[primitive].tangents; }
    // The posed model's bounds in model space (the last finite ones).
    [[nodiscard]] glm::vec3 boundsMin() const { return boundsMin_; }
    [[nodiscard]] glm::vec3 boundsMax() const { return boundsMax_; }

private:
    struct NodePose {
        glm::vec3 translation{0.0f};
        glm::quat rotation{1.0f, 0.0f, 0.0f, 0.0f};
        glm::vec3 scale{1.0f};
        std::vector<float> weights;
    };
    struct PosedVertices {
        std::vector<glm::vec3> positions;
        std::vector<glm::vec3> normals;
        std::vector<glm::vec4> tangents;
    };
    void applyClip(const ClipTime& clip);
    void poseVertices(size_t primitive);

    std::shared_ptr<const GltfRig> rig_;
    std::vector<NodePose> nodes_;
    std::vector<glm::mat4> modelFromNode_;
    std::vector<std::vector<glm::mat4>> jointMatrices_; // per skin
    std::vector<glm::mat4> modelFromMesh_;
    std::vector<PosedVertices> posed_;
    std::vector<float> sample_; // scratch: one sampler's value
    glm::vec3 boundsMin_{0.0f}, boundsMax_{0.0f};
};

// Writes the poser's current pose into `primitives` (the model's, in the rig's order):
// their transforms and, for deforming ones, their vertices.
void applyPose(const ModelPoser& poser, std::vector<GltfPrimitive>& primitives);

} // namespace lumar
