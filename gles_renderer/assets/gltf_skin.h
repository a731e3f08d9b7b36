// Vertex deformation as glTF 2.0 defines it (§3.7.3): morph targets (weighted displacements of
// positions, normals and tangents) and skinning (each vertex moved by up to four joints per
// JOINTS_n/WEIGHTS_n set). Plain CPU arrays: the renderer poses vertices on the CPU
// (gles_renderer/scene/model_pose_upload.h says why).
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include <glm/glm.hpp>

namespace lumar {

// One JOINTS_n / WEIGHTS_n pair: four influences per vertex, joint indices into the skin's joints.
struct JointInfluences {
    std::vector<glm::u16vec4> joints;
    std::vector<glm::vec4> weights;
};

// One morph target's displacements; an attribute the target does not move is empty.
struct MorphTarget {
    std::vector<glm::vec3> positions;
    std::vector<glm::vec3> normals;
    std::vector<glm::vec3> tangents; // xyz only: the handedness never changes
};

// A vertex set being deformed: its arrays are all the same length (tangents may be empty).
struct VertexArrays {
    std::span<glm::vec3> positions;
    std::span<glm::vec3> normals;
    std::span<glm::vec4> tangents;
};
struct ConstVertexArrays {
    std::span<const glm::vec3> positions;
    std::span<const glm::vec3> normals;
    std::span<const glm::vec4> tangents;
};

// out = base + sum of weights[k] * targets[k] (targets with a zero weight skipped); the
// normals and tangents made unit length again. `out` may alias `base`.
void applyMorphTargets(ConstVertexArrays base, std::span<const MorphTarget> targets, std::span<const float> weights,
                       VertexArrays out);

// Linear blend skinning: each vertex moved by sum_i w_i * jointMatrices[j_i] (the weights
// renormalised where their sum is not 1; a vertex whose weights are all zero stays where it
// is). Normals and tangents are turned by the blended matrix's linear part and made unit
// length: exact for rotations and uniform scales, which is what rigs use. Joint indices must be
// below jointMatrices.size() (the loader checks). `out` may alias `in`.
void skinVertices(std::span<const glm::mat4> jointMatrices, std::span<const JointInfluences> influences,
                  ConstVertexArrays in, VertexArrays out);

} // namespace lumar
