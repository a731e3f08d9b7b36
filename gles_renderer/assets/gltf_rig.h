// What a glTF model needs to move (glTF 2.0 §3.5, §3.7.3, §3.8, §3.11): its node hierarchy with
// each node's rest transform, its skins, its animations, and for each of the model's
// primitives the node it hangs from and what deforms it (joint influences, morph targets).
// GltfModel::rig holds one for models with animations; the loader poses a model without
// animations once (model_pose.h) and keeps no rig.
#pragma once

#include <memory>
#include <optional>
#include <vector>

#include <glm/glm.hpp>
#include <glm/gtc/quaternion.hpp>

#include "gles_renderer/assets/gltf_animation.h"
#include "gles_renderer/assets/gltf_skin.h"

namespace lumar {

struct RigNode {
    int parent = -1;
    // The rest transform: translation * rotation * scale, or a fixed matrix (never animated).
    glm::vec3 translation{0.0f};
    glm::quat rotation{1.0f, 0.0f, 0.0f, 0.0f};
    glm::vec3 scale{1.0f};
    std::optional<glm::mat4> matrix;
    // Morph weights at rest (the node's, else its mesh's, else zeros), one per morph target
    // of its mesh; empty when the mesh has none.
    std::vector<float> weights;
};

struct RigSkin {
    std::vector<int> joints;                    // node indices
    std::vector<glm::mat4> inverseBindMatrices; // one per joint (identity when the file has none)
};

// What deforms one mesh primitive: shared by every instance of it.
struct PrimitiveDeformation {
    // The primitive as the file has it, in mesh space: what skinning and morphing start from.
    std::vector<glm::vec3> positions;
    std::vector<glm::vec3> normals;
    std::vector<glm::vec4> tangents;
    std::vector<JointInfluences> influences; // empty: not skinned
    std::vector<MorphTarget> targets;        // empty: no morph targets
};

struct RiggedPrimitive {
    int node = -1; // the node whose mesh it is an instance of
    int skin = -1; // that node's skin, -1: none
    // The primitive's place below its node (identity unless the loader put more beneath it,
    // such as an instance transform): modelFromMesh = modelFromNode * nodeFromMesh.
    glm::mat4 nodeFromMesh{1.0f};
    glm::vec3 meshBoundsMin{0.0f}, meshBoundsMax{0.0f};      // of the undeformed primitive, mesh space
    std::shared_ptr<const PrimitiveDeformation> deformation; // null: moved only by its node
};

struct GltfRig {
    std::vector<RigNode> nodes;
    std::vector<int> order; // every node, parents before their children
    std::vector<RigSkin> skins;
    std::vector<Animation> animations;
    std::vector<RiggedPrimitive> primitives; // parallel to GltfModel::primitives
    // Whether any primitive is skinned or morphed (else the pose only moves transforms).
    [[nodiscard]] bool deforms() const
    {
        for (const RiggedPrimitive& p : primitives)
            if (p.deformation)
                return true;
        return false;
    }
};

} // namespace lumar
