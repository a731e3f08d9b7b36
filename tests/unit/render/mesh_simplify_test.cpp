// Stand-ins for the environment maps (meshoptimizer edge collapse): far fewer triangles on a
// dense mesh, every original vertex within a cell of the stand-in's surface, the stand-in's
// vertices original ones with their attributes, nothing degenerate or unused, fewer
// triangles the coarser the level, bad input rejected.
#include <algorithm>
#include <cmath>
#include <limits>

#include <gtest/gtest.h>

#include "core/error.h"
#include "gles_renderer/assets/builtin_shapes.h"
#include "gles_renderer/assets/mesh_simplify.h"

namespace lumar {
namespace {

// Distance from p to triangle abc (closest point by region, Ericson's Real-Time Collision
// Detection 5.1.5).
float distanceToTriangle(glm::vec3 p, glm::vec3 a, glm::vec3 b, glm::vec3 c)
{
    const glm::vec3 ab = b - a, ac = c - a, ap = p - a;
    const float d1 = glm::dot(ab, ap), d2 = glm::dot(ac, ap);
    if (d1 <= 0.0f && d2 <= 0.0f)
        return glm::length(p - a);
    const glm::vec3 bp = p - b;
    const float d3 = glm::dot(ab, bp), d4 = glm::dot(ac, bp);
    if (d3 >= 0.0f && d4 <= d3)
        return glm::length(p - b);
    const float vc = d1 * d4 - d3 * d2;
    if (vc <= 0.0f && d1 >= 0.0f && d3 <= 0.0f)
        return glm::length(p - (a + ab * (d1 / (d1 - d3))));
    const glm::vec3 cp = p - c;
    const float d5 = glm::dot(ab, cp), d6 = glm::dot(ac, cp);
    if (d6 >= 0.0f && d5 <= d6)
        return glm::length(p - c);
    const float vb = d5 * d2 - d1 * d6;
    if (vb <= 0.0f && d2 >= 0.0f && d6 <= 0.0f)
        return glm::length(p - (a + ac * (d2 / (d2 - d6))));
    const float va = d3 * d6 - d5 * d4;
    if (va <= 0.0f && d4 - d3 >= 0.0f && d5 - d6 >= 0.0f)
        return glm::length(p - (b + (c - b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6)))));
    const float denom = 1.0f / (va + vb + vc);
    return glm::length(p - (a + ab * (vb * denom) + ac * (vc * denom)));
}

// The furthest any vertex of `original` lies from the surface of `simplified`.
float maxDistanceToSurface(const GltfPrimitive& original, const GltfPrimitive& simplified)
{
    float furthest = 0.0f;
    for (const glm::vec3& v : original.positions) {
        float nearest = std::numeric_limits<float>::infinity();
        for (size_t t = 0; t + 2 < simplified.indices.size(); t += 3)
            nearest = std::min(nearest, distanceToTriangle(v, simplified.positions[simplified.indices[t]],
                                                           simplified.positions[simplified.indices[t + 1]],
                                                           simplified.positions[simplified.indices[t + 2]]));
        furthest = std::max(furthest, nearest);
    }
    return furthest;
}

// Valid, non-degenerate triangles over vertices that are all used, attribute arrays alike.
void expectWellFormed(const GltfPrimitive& p)
{
    ASSERT_EQ(p.positions.size(), p.normals.size());
    ASSERT_EQ(p.positions.size(), p.uvs.size());
    ASSERT_EQ(p.positions.size(), p.tangents.size());
    ASSERT_EQ(p.indices.size() % 3, 0u);
    std::vector<bool> used(p.positions.size(), false);
    for (size_t t = 0; t < p.indices.size(); t += 3) {
        for (size_t k = 0; k < 3; ++k) {
            ASSERT_LT(p.indices[t + k], p.positions.size());
            used[p.indices[t + k]] = true;
        }
        EXPECT_NE(p.indices[t], p.indices[t + 1]);
        EXPECT_NE(p.indices[t + 1], p.indices[t + 2]);
        EXPECT_NE(p.indices[t], p.indices[t + 2]);
    }
    EXPECT_EQ(std::count(used.begin(), used.end(), false), 0) << "stand-ins carry only the vertices they use";
}

TEST(MeshSimplify, ADenseSphereKeepsItsShapeWithFarFewerTriangles)
{
    const GltfModel sphere = makeUvSphere(128, 64); // radius 0.5, bounds 1 across
    const GltfPrimitive& original = sphere.primitives[0];
    const size_t before = original.indices.size() / 3;
    const GltfModel proxy = makeProxyModel(sphere, 16); // cells of 1/16
    const GltfPrimitive& p = proxy.primitives[0];
    const size_t after = p.indices.size() / 3;
    EXPECT_LT(after, before / 10) << before << " -> " << after; // measured 16128 -> 601
    EXPECT_GT(after, 50u);                                      // still a sphere, not a handful of triangles
    expectWellFormed(p);
    EXPECT_EQ(p.material, original.material);
    EXPECT_EQ(p.modelFromMesh, original.modelFromMesh);
    EXPECT_LT(maxDistanceToSurface(original, p), 1.0f / 16.0f); // measured 0.33 cell

    // Collapses keep original vertices and their attributes: on the sphere, unit normals
    // pointing along the position, tangents along the parallels.
    for (size_t i = 0; i < p.positions.size(); ++i) {
        EXPECT_NEAR(glm::length(p.positions[i]), 0.5f, 1e-5f);
        EXPECT_NEAR(glm::length(p.normals[i] - 2.0f * p.positions[i]), 0.0f, 1e-5f);
        EXPECT_NEAR(p.tangents[i].y, 0.0f, 1e-5f);
        EXPECT_EQ(p.tangents[i].w, 1.0f);
    }
    // Its bounds stay those of the sphere within a cell.
    glm::vec3 lo(std::numeric_limits<float>::infinity()), hi(-std::numeric_limits<float>::infinity());
    for (const glm::vec3& v : p.positions) {
        lo = glm::min(lo, v);
        hi = glm::max(hi, v);
    }
    for (int c = 0; c < 3; ++c) {
        EXPECT_NEAR(lo[c], sphere.boundsMin[c], 1.0f / 16.0f);
        EXPECT_NEAR(hi[c], sphere.boundsMax[c], 1.0f / 16.0f);
    }
}

TEST(MeshSimplify, CoarserLevelsHaveFewerTrianglesAndStayWithinTheirCell)
{
    const GltfModel sphere = makeUvSphere(64, 32);
    size_t previous = sphere.primitives[0].indices.size() / 3;
    for (const int cells : {48, 32, 24, 16, 12, 8}) {
        const GltfPrimitive p = makeProxyModel(sphere, cells).primitives[0];
        expectWellFormed(p);
        const size_t triangles = p.indices.size() / 3;
        EXPECT_LE(triangles, previous) << cells << " cells";
        // Measured 0.32 to 0.43 cell.
        EXPECT_LT(maxDistanceToSurface(sphere.primitives[0], p), 1.0f / float(cells)) << cells << " cells";
        previous = triangles;
    }
    EXPECT_LT(previous, sphere.primitives[0].indices.size() / 3 / 10); // measured 3968 -> 305 at 8 cells
}

TEST(MeshSimplify, TheLevelIsRelativeToTheModelWhateverThePrimitivesScale)
{
    // The same sphere, its mesh coordinates 4x smaller and its transform scaling them back.
    const GltfModel sphere = makeUvSphere(64, 32);
    GltfModel small = sphere;
    GltfPrimitive& p = small.primitives[0];
    for (glm::vec3& v : p.positions)
        v *= 0.25f;
    p.modelFromMesh = glm::mat4(glm::mat3(4.0f));
    const size_t expected = makeProxyModel(sphere, 16).primitives[0].indices.size();
    const size_t actual = makeProxyModel(small, 16).primitives[0].indices.size();
    EXPECT_NEAR(double(actual), double(expected), 0.05 * double(expected));
    EXPECT_LT(actual, p.indices.size() / 4);
}

TEST(MeshSimplify, ACoarseMeshIsLeftAloneAndDegenerateOnesPassThrough)
{
    const GltfModel cube = makeCube();
    const GltfModel proxy = makeProxyModel(cube, 64);
    EXPECT_EQ(proxy.primitives[0].indices.size(), cube.primitives[0].indices.size());
    expectWellFormed(proxy.primitives[0]);

    GltfPrimitive empty; // no triangles
    EXPECT_TRUE(simplifyPrimitive(empty, 0.1f).indices.empty());
    GltfPrimitive point = cube.primitives[0]; // every vertex at one place: nothing to measure
    std::fill(point.positions.begin(), point.positions.end(), glm::vec3(1.0f));
    EXPECT_EQ(simplifyPrimitive(point, 0.1f).indices, point.indices);
    GltfModel flat = cube; // zero-size bounds: the level has no cell
    flat.boundsMax = flat.boundsMin;
    EXPECT_EQ(makeProxyModel(flat, 8).primitives[0].indices, cube.primitives[0].indices);
}

TEST(MeshSimplify, TheProxyPrimitivesAreTheProxyModelsInTheModelsOrder)
{
    GltfModel model = makeUvSphere(64, 32);
    model.primitives.push_back(makeCube().primitives[0]);
    const GltfModel proxy = makeProxyModel(model, 16);
    const std::vector<GltfPrimitive> primitives = makeProxyPrimitives(model, 16);
    ASSERT_EQ(primitives.size(), model.primitives.size());
    for (size_t i = 0; i < primitives.size(); ++i) {
        EXPECT_EQ(primitives[i].indices, proxy.primitives[i].indices) << i;
        EXPECT_EQ(primitives[i].positions, proxy.primitives[i].positions) << i;
    }
    EXPECT_LT(primitives[0].indices.size(), model.primitives[0].indices.size() / 2);
    EXPECT_THROW(makeProxyPrimitives(model, 0), InputError);
}

TEST(MeshSimplify, BadArgumentsAndMalformedPrimitivesAreRejected)
{
    const GltfModel cube = makeCube();
    const GltfPrimitive& p = cube.primitives[0];
    EXPECT_THROW(simplifyPrimitive(p, 0.0f), InputError);
    EXPECT_THROW(simplifyPrimitive(p, -1.0f), InputError);
    EXPECT_THROW(simplifyPrimitive(p, std::numeric_limits<float>::quiet_NaN()), InputError);
    EXPECT_THROW(simplifyPrimitive(p, std::numeric_limits<float>::infinity()), InputError);
    EXPECT_THROW(makeProxyModel(cube, 0), InputError);

    GltfPrimitive outOfRange = p;
    outOfRange.indices[4] = uint32_t(p.positions.size());
    EXPECT_THROW(simplifyPrimitive(outOfRange, 0.1f), InputError);
    GltfPrimitive partial = p;
    partial.indices.pop_back();
    EXPECT_THROW(simplifyPrimitive(partial, 0.1f), InputError);
    GltfPrimitive mismatched = p;
    mismatched.uvs.pop_back();
    EXPECT_THROW(simplifyPrimitive(mismatched, 0.1f), InputError);
}

} // namespace
} // namespace lumar
