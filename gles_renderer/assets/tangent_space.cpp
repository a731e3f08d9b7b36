#include "gles_renderer/assets/tangent_space.h"

#include <algorithm>
#include <cmath>

namespace lumar {
namespace {

// Any unit vector orthogonal to the unit vector n: cross n with the coordinate axis least
// aligned with it, so the cross product never degenerates.
glm::vec3 anyOrthogonal(const glm::vec3& n)
{
    const glm::vec3 axis = std::abs(n.x) < 0.9f ? glm::vec3(1, 0, 0) : glm::vec3(0, 1, 0);
    return glm::normalize(glm::cross(n, axis));
}

// Interior angle at corner `a` of triangle (a, b, c); 0 for a degenerate corner.
float cornerAngle(const glm::vec3& a, const glm::vec3& b, const glm::vec3& c)
{
    const glm::vec3 e1 = b - a;
    const glm::vec3 e2 = c - a;
    const float l1 = glm::length(e1);
    const float l2 = glm::length(e2);
    if (l1 <= 0.0f || l2 <= 0.0f) {
        return 0.0f;
    }
    return std::acos(std::clamp(glm::dot(e1, e2) / (l1 * l2), -1.0f, 1.0f));
}

} // namespace

std::vector<glm::vec3> generateVertexNormals(std::span<const glm::vec3> positions, std::span<const uint32_t> indices)
{
    std::vector<glm::vec3> sum(positions.size(), glm::vec3(0.0f));
    for (size_t t = 0; t + 2 < indices.size(); t += 3) {
        const uint32_t i0 = indices[t], i1 = indices[t + 1], i2 = indices[t + 2];
        // The cross product's length is twice the triangle's area: that is the weighting.
        const glm::vec3 faceNormal = glm::cross(positions[i1] - positions[i0], positions[i2] - positions[i0]);
        sum[i0] += faceNormal;
        sum[i1] += faceNormal;
        sum[i2] += faceNormal;
    }
    for (glm::vec3& n : sum) {
        const float length = glm::length(n);
        n = length > 0.0f && std::isfinite(length) ? n / length : glm::vec3(0, 0, 1);
    }
    return sum;
}

std::vector<glm::vec4> generateTangents(std::span<const glm::vec3> positions, std::span<const glm::vec3> normals,
                                        std::span<const glm::vec2> uvs, std::span<const uint32_t> indices)
{
    std::vector<glm::vec3> alongU(positions.size(), glm::vec3(0.0f));
    std::vector<glm::vec3> upImage(positions.size(), glm::vec3(0.0f));

    for (size_t t = 0; t + 2 < indices.size(); t += 3) {
        const uint32_t corner[3] = {indices[t], indices[t + 1], indices[t + 2]};
        const glm::vec3 dp1 = positions[corner[1]] - positions[corner[0]];
        const glm::vec3 dp2 = positions[corner[2]] - positions[corner[0]];
        const glm::vec2 duv1 = uvs[corner[1]] - uvs[corner[0]];
        const glm::vec2 duv2 = uvs[corner[2]] - uvs[corner[0]];
        const float det = duv1.x * duv2.y - duv2.x * duv1.y;
        if (std::abs(det) < 1e-20f) {
            continue; // the uvs collapse this triangle: no direction to learn from it
        }
        // Solve dp = dP/du * du + dP/dv * dv for the two edges.
        const glm::vec3 dPdu = (dp1 * duv2.y - dp2 * duv1.y) / det;
        const glm::vec3 dPdv = (dp2 * duv1.x - dp1 * duv2.x) / det;
        const float lu = glm::length(dPdu);
        const float lv = glm::length(dPdv);
        if (!(lu > 0.0f) || !(lv > 0.0f) || !std::isfinite(lu) || !std::isfinite(lv)) {
            continue;
        }
        const glm::vec3 tangentDir = dPdu / lu;
        const glm::vec3 imageUpDir = -dPdv / lv; // glTF's v grows down the image
        for (int k = 0; k < 3; ++k) {
            const float weight =
                cornerAngle(positions[corner[k]], positions[corner[(k + 1) % 3]], positions[corner[(k + 2) % 3]]);
            alongU[corner[k]] += weight * tangentDir;
            upImage[corner[k]] += weight * imageUpDir;
        }
    }

    std::vector<glm::vec4> tangents(positions.size());
    for (size_t i = 0; i < positions.size(); ++i) {
        const glm::vec3& n = normals[i];
        glm::vec3 t = alongU[i] - n * glm::dot(n, alongU[i]);
        const float length = glm::length(t);
        if (!(length > 1e-12f) || !std::isfinite(length)) {
            tangents[i] = glm::vec4(anyOrthogonal(n), 1.0f);
            continue;
        }
        t /= length;
        const float handedness = glm::dot(glm::cross(n, t), upImage[i]) < 0.0f ? -1.0f : 1.0f;
        tangents[i] = glm::vec4(t, handedness);
    }
    return tangents;
}

std::span<const glm::vec2> normalMapUvs(int normalTexCoord, std::span<const glm::vec2> uvs0,
                                        std::span<const glm::vec2> uvs1)
{
    return normalTexCoord == 1 && uvs1.size() == uvs0.size() ? uvs1 : uvs0;
}

} // namespace lumar
