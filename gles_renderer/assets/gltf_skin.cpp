#include "gles_renderer/assets/gltf_skin.h"

#include <cmath>
#include <cstddef>

namespace lumar {
namespace {

glm::vec3 unitOr(const glm::vec3& v, const glm::vec3& fallback)
{
    const float length = glm::length(v);
    return length > 1e-20f ? v / length : fallback;
}

} // namespace

void applyMorphTargets(ConstVertexArrays base, std::span<const MorphTarget> targets, std::span<const float> weights,
                       VertexArrays out)
{
    const size_t n = base.positions.size();
    const bool hasNormals = !base.normals.empty(), hasTangents = !base.tangents.empty();
    if (out.positions.data() != base.positions.data())
        std::copy(base.positions.begin(), base.positions.end(), out.positions.begin());
    if (hasNormals && out.normals.data() != base.normals.data())
        std::copy(base.normals.begin(), base.normals.end(), out.normals.begin());
    if (hasTangents && out.tangents.data() != base.tangents.data())
        std::copy(base.tangents.begin(), base.tangents.end(), out.tangents.begin());
    bool turned = false;
    for (size_t k = 0; k < targets.size() && k < weights.size(); ++k) {
        const float w = weights[k];
        if (w == 0.0f)
            continue;
        const MorphTarget& target = targets[k];
        if (!target.positions.empty())
            for (size_t i = 0; i < n; ++i)
                out.positions[i] += w * target.positions[i];
        if (hasNormals && !target.normals.empty()) {
            turned = true;
            for (size_t i = 0; i < n; ++i)
                out.normals[i] += w * target.normals[i];
        }
        if (hasTangents && !target.tangents.empty()) {
            turned = true;
            for (size_t i = 0; i < n; ++i)
                out.tangents[i] += glm::vec4(w * target.tangents[i], 0.0f);
        }
    }
    if (!turned)
        return;
    for (size_t i = 0; hasNormals && i < n; ++i)
        out.normals[i] = unitOr(out.normals[i], base.normals[i]);
    for (size_t i = 0; hasTangents && i < n; ++i)
        out.tangents[i] =
            glm::vec4(unitOr(glm::vec3(out.tangents[i]), glm::vec3(base.tangents[i])), base.tangents[i].w);
}

void skinVertices(std::span<const glm::mat4> jointMatrices, std::span<const JointInfluences> influences,
                  ConstVertexArrays in, VertexArrays out)
{
    const size_t n = in.positions.size();
    const bool hasNormals = !in.normals.empty(), hasTangents = !in.tangents.empty();
    for (size_t i = 0; i < n; ++i) {
        glm::mat4 m(0.0f);
        float total = 0.0f;
        for (const JointInfluences& set : influences) {
            const glm::u16vec4 j = set.joints[i];
            const glm::vec4 w = set.weights[i];
            for (int c = 0; c < 4; ++c) {
                if (w[c] != 0.0f) {
                    m += w[c] * jointMatrices[j[c]];
                    total += w[c];
                }
            }
        }
        if (!(total > 0.0f)) {
            // No influence: the vertex stays as it is (out may alias in).
            out.positions[i] = in.positions[i];
            if (hasNormals)
                out.normals[i] = in.normals[i];
            if (hasTangents)
                out.tangents[i] = in.tangents[i];
            continue;
        }
        if (std::abs(total - 1.0f) > 1e-4f) // exporters' rounding, or quantised weights
            m *= 1.0f / total;
        const glm::mat3 linear(m);
        out.positions[i] = glm::vec3(m * glm::vec4(in.positions[i], 1.0f));
        if (hasNormals)
            out.normals[i] = unitOr(linear * in.normals[i], in.normals[i]);
        if (hasTangents) {
            const glm::vec4 t = in.tangents[i];
            out.tangents[i] = glm::vec4(unitOr(linear * glm::vec3(t), glm::vec3(t)), t.w);
        }
    }
}

} // namespace lumar
