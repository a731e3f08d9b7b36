// Vertex clustering for the environment-map stand-ins: far fewer triangles on a dense mesh,
// the surface kept within a cell of the original, nothing degenerate, indices valid.
#include <gtest/gtest.h>

#include "core/error.h"
#include "gles_renderer/assets/builtin_shapes.h"
#include "gles_renderer/assets/mesh_simplify.h"

namespace lumar {
namespace {

TEST(MeshSimplify, ClusteringASphereKeepsItsShapeWithFarFewerTriangles)
{
    const GltfModel sphere = makeUvSphere(128, 64); // radius 0.5
    const size_t before = sphere.primitives[0].indices.size() / 3;
    const GltfModel proxy = makeProxyModel(sphere, 16); // cells of 1/16
    const GltfPrimitive& p = proxy.primitives[0];
    const size_t after = p.indices.size() / 3;
    EXPECT_LT(after, before / 6) << before << " -> " << after; // measured 16128 -> 2152
    EXPECT_GT(after, 200u);                                    // still a sphere, not a handful of triangles
    for (const glm::vec3& v : p.positions)
        EXPECT_NEAR(glm::length(v), 0.5f, 1.0f / 16.0f); // within a cell of the surface
    for (size_t t = 0; t < p.indices.size(); t += 3) {
        ASSERT_LT(p.indices[t], p.positions.size());
        ASSERT_LT(p.indices[t + 1], p.positions.size());
        ASSERT_LT(p.indices[t + 2], p.positions.size());
        EXPECT_NE(p.indices[t], p.indices[t + 1]);
        EXPECT_NE(p.indices[t + 1], p.indices[t + 2]);
        EXPECT_NE(p.indices[t], p.indices[t + 2]);
    }
    for (size_t i = 0; i < p.normals.size(); ++i) // outward normals survive the averaging
        EXPECT_GT(glm::dot(p.normals[i], glm::normalize(p.positions[i])), 0.9f);
    EXPECT_EQ(p.positions.size(), p.normals.size());
    EXPECT_EQ(p.positions.size(), p.uvs.size());
    EXPECT_EQ(p.positions.size(), p.tangents.size());
    EXPECT_EQ(p.material, sphere.primitives[0].material);
}

TEST(MeshSimplify, ACoarseMeshIsLeftAloneAndBadCellsAreRejected)
{
    const GltfModel cube = makeCube();
    const GltfModel proxy = makeProxyModel(cube, 64);
    EXPECT_EQ(proxy.primitives[0].indices.size(), cube.primitives[0].indices.size());
    EXPECT_THROW(simplifyByClustering(cube.primitives[0], 0.0f), InputError);
    EXPECT_THROW(makeProxyModel(cube, 0), InputError);
}

} // namespace
} // namespace lumar
