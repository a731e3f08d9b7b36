// The built-in shapes (phantoms' plane and cylinder, objects' sphere and cube): front faces
// wind counter-clockwise seen from outside (the geometric normal agrees with the vertex
// normals), tangents follow the uvs with the same handedness convention in every shape
// (normal x tangent x w points where v decreases, glTF's flipped v), and the bounds hold
// every vertex.
#include <glm/glm.hpp>
#include <gtest/gtest.h>

#include "gles_renderer/assets/builtin_shapes.h"

namespace lumar {
namespace {

void expectConsistent(const GltfModel& model)
{
    ASSERT_EQ(model.primitives.size(), 1u);
    const GltfPrimitive& p = model.primitives[0];
    ASSERT_EQ(p.normals.size(), p.positions.size());
    ASSERT_EQ(p.uvs.size(), p.positions.size());
    ASSERT_EQ(p.tangents.size(), p.positions.size());
    ASSERT_EQ(p.indices.size() % 3, 0u);
    for (const glm::vec3& x : p.positions)
        for (int a = 0; a < 3; ++a) {
            EXPECT_GE(x[a], model.boundsMin[a] - 1e-6f);
            EXPECT_LE(x[a], model.boundsMax[a] + 1e-6f);
        }
    for (size_t i = 0; i < p.positions.size(); ++i) {
        EXPECT_NEAR(glm::length(p.normals[i]), 1.0f, 1e-5f);
        EXPECT_NEAR(glm::length(glm::vec3(p.tangents[i])), 1.0f, 1e-5f);
        EXPECT_NEAR(glm::dot(p.normals[i], glm::vec3(p.tangents[i])), 0.0f, 1e-5f);
    }
    for (size_t t = 0; t < p.indices.size(); t += 3) {
        const uint32_t a = p.indices[t], b = p.indices[t + 1], c = p.indices[t + 2];
        const glm::vec3 e1 = p.positions[b] - p.positions[a], e2 = p.positions[c] - p.positions[a];
        const glm::vec3 geometric = glm::cross(e1, e2);
        if (glm::length(geometric) < 1e-9f)
            continue; // a degenerate triangle (a pole) has no winding
        for (const uint32_t v : {a, b, c})
            EXPECT_GT(glm::dot(geometric, p.normals[v]), 0.0f) << model.file << " triangle " << t / 3;
        // The uv gradient over the triangle: where u and v grow in space.
        const glm::vec2 d1 = p.uvs[b] - p.uvs[a], d2 = p.uvs[c] - p.uvs[a];
        const float det = d1.x * d2.y - d2.x * d1.y;
        if (std::abs(det) < 1e-9f)
            continue;
        const glm::vec3 alongU = (e1 * d2.y - e2 * d1.y) / det;
        const glm::vec3 alongV = (e2 * d1.x - e1 * d2.x) / det;
        const glm::vec4& tangent = p.tangents[a];
        const glm::vec3 bitangent = glm::cross(p.normals[a], glm::vec3(tangent)) * tangent.w;
        EXPECT_GT(glm::dot(glm::vec3(tangent), alongU), 0.0f) << model.file << " triangle " << t / 3;
        EXPECT_LT(glm::dot(bitangent, alongV), 0.0f) << model.file << " triangle " << t / 3;
    }
}

TEST(BuiltinShapes, WindingNormalsAndTangentsAgree)
{
    for (const GltfModel& model : {makeCube(), makeUvSphere(16, 8), makePlane(), makeCylinder(12)}) {
        SCOPED_TRACE(model.file.string());
        expectConsistent(model);
    }
}

TEST(BuiltinShapes, PlaneAndCylinderSpanTheUnitBox)
{
    const GltfModel plane = makePlane();
    EXPECT_EQ(plane.boundsMin, glm::vec3(-0.5f, 0.0f, -0.5f));
    EXPECT_EQ(plane.boundsMax, glm::vec3(0.5f, 0.0f, 0.5f));
    EXPECT_TRUE(plane.materials[0].doubleSided);
    const GltfModel cylinder = makeCylinder(32);
    EXPECT_EQ(cylinder.boundsMin, glm::vec3(-0.5f));
    EXPECT_EQ(cylinder.boundsMax, glm::vec3(0.5f));
    float radius = 0.0f;
    for (const glm::vec3& x : cylinder.primitives[0].positions)
        radius = std::max(radius, std::hypot(x.x, x.z));
    EXPECT_NEAR(radius, 0.5f, 1e-6f);
}

} // namespace
} // namespace lumar
