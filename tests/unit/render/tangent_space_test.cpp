// Generated normals and tangents on small meshes whose answers are known by construction.
#include <cmath>
#include <vector>

#include <gtest/gtest.h>

#include "gles_renderer/assets/tangent_space.h"

namespace lumar {
namespace {

// A unit quad in the xy-plane facing +z, two counter-clockwise triangles.
const std::vector<glm::vec3> kQuad = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
const std::vector<uint32_t> kQuadIndices = {0, 1, 2, 0, 2, 3};
const std::vector<glm::vec3> kQuadNormals(4, glm::vec3(0, 0, 1));

void expectTangents(const std::vector<glm::vec4>& tangents, const glm::vec3& direction, float w)
{
    ASSERT_EQ(tangents.size(), 4u);
    for (const glm::vec4& t : tangents) {
        EXPECT_NEAR(glm::distance(glm::vec3(t), direction), 0.0f, 1e-6f);
        EXPECT_EQ(t.w, w);
    }
}

TEST(TangentSpace, UnmirroredUvsGiveTangentAlongUAndPositiveHandedness)
{
    // glTF uvs: v = 0 is the top of the image, so the quad's top edge (y = 1) has v = 0.
    // +u runs along +x, "up the image" along +y = cross(N, T): w = +1.
    const std::vector<glm::vec2> uvs = {{0, 1}, {1, 1}, {1, 0}, {0, 0}};
    expectTangents(generateTangents(kQuad, kQuadNormals, uvs, kQuadIndices), {1, 0, 0}, 1.0f);
}

TEST(TangentSpace, UvsMirroredInUFlipTheTangentAndTheHandedness)
{
    const std::vector<glm::vec2> uvs = {{1, 1}, {0, 1}, {0, 0}, {1, 0}};
    // +u now runs along -x; up the image is still +y, but cross(N, -x) = -y: w = -1.
    expectTangents(generateTangents(kQuad, kQuadNormals, uvs, kQuadIndices), {-1, 0, 0}, -1.0f);
}

TEST(TangentSpace, UvsMirroredInVKeepTheTangentButFlipTheHandedness)
{
    const std::vector<glm::vec2> uvs = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
    // +u along +x, up the image now -y, cross(N, +x) = +y: w = -1.
    expectTangents(generateTangents(kQuad, kQuadNormals, uvs, kQuadIndices), {1, 0, 0}, -1.0f);
}

TEST(TangentSpace, RotatedUvsAndGramSchmidtAgainstTheNormal)
{
    // uvs rotated 90 degrees: +u runs along +y. The vertex normals are tilted towards +x, so
    // the tangent is +y made orthogonal to them: (+y - n (n.y)) = +y since n.y = 0.
    const std::vector<glm::vec2> uvs = {{0, 0}, {0, 1}, {1, 1}, {1, 0}};
    const glm::vec3 tilted = glm::normalize(glm::vec3(0.3f, 0, 1));
    const std::vector<glm::vec3> normals(4, tilted);
    const auto tangents = generateTangents(kQuad, normals, uvs, kQuadIndices);
    for (const glm::vec4& t : tangents) {
        EXPECT_NEAR(glm::distance(glm::vec3(t), glm::vec3(0, 1, 0)), 0.0f, 1e-6f);
        EXPECT_NEAR(glm::dot(glm::vec3(t), tilted), 0.0f, 1e-6f);
        // Up the image (-v) is -x here and cross(n, +y) = (-n.z, 0, n.x) also points along
        // -x: not mirrored, w = +1.
        EXPECT_EQ(t.w, 1.0f);
    }
}

TEST(TangentSpace, DegenerateUvsStillGiveAUnitTangentOrthogonalToTheNormal)
{
    const std::vector<glm::vec2> uvs(4, glm::vec2(0.5f));
    for (const glm::vec4& t : generateTangents(kQuad, kQuadNormals, uvs, kQuadIndices)) {
        EXPECT_NEAR(glm::length(glm::vec3(t)), 1.0f, 1e-6f);
        EXPECT_NEAR(glm::dot(glm::vec3(t), glm::vec3(0, 0, 1)), 0.0f, 1e-6f);
        EXPECT_EQ(t.w, 1.0f);
    }
}

TEST(TangentSpace, NormalsAreAreaWeighted)
{
    // Vertex 0 is shared by a large triangle facing +z (area 2) and a small one facing +x
    // (area 0.5): its normal is (0.5, 0, 2) normalised; unshared vertices keep their face's.
    const std::vector<glm::vec3> positions = {{0, 0, 0}, {2, 0, 0}, {0, 2, 0}, {0, 1, 0}, {0, 0, 1}};
    const std::vector<uint32_t> indices = {0, 1, 2, 0, 3, 4};
    const auto normals = generateVertexNormals(positions, indices);
    ASSERT_EQ(normals.size(), 5u);
    EXPECT_NEAR(glm::distance(normals[0], glm::normalize(glm::vec3(0.5f, 0, 2))), 0.0f, 1e-6f);
    EXPECT_NEAR(glm::distance(normals[1], glm::vec3(0, 0, 1)), 0.0f, 1e-6f);
    EXPECT_NEAR(glm::distance(normals[3], glm::vec3(1, 0, 0)), 0.0f, 1e-6f);
}

TEST(TangentSpace, UnusedAndDegenerateVerticesGetAUnitNormal)
{
    const std::vector<glm::vec3> positions = {{0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {5, 5, 5}};
    const std::vector<uint32_t> indices = {0, 1, 2}; // collinear: zero area
    for (const glm::vec3& n : generateVertexNormals(positions, indices)) {
        EXPECT_NEAR(glm::length(n), 1.0f, 1e-6f);
    }
}

TEST(TangentSpace, NormalMapUvsPickTheSetTheNormalMapReads)
{
    const std::vector<glm::vec2> first(4, glm::vec2(0.0f)), second(4, glm::vec2(1.0f)), none;
    EXPECT_EQ(normalMapUvs(0, first, second).data(), first.data());
    EXPECT_EQ(normalMapUvs(1, first, second).data(), second.data());
    // TEXCOORD_1 named but absent (or not one per vertex): the first set.
    EXPECT_EQ(normalMapUvs(1, first, none).data(), first.data());
    // Tangents from the second set: the quad's uvs turned a quarter, so +u runs along -y.
    const std::vector<glm::vec2> straight = {{0, 1}, {1, 1}, {1, 0}, {0, 0}}, turned = {{1, 0}, {1, 1}, {0, 1}, {0, 0}};
    for (const glm::vec4& t : generateTangents(kQuad, kQuadNormals, normalMapUvs(1, straight, turned), kQuadIndices))
        EXPECT_NEAR(glm::dot(glm::vec3(t), glm::vec3(0, -1, 0)), 1.0f, 1e-5f);
    for (const glm::vec4& t : generateTangents(kQuad, kQuadNormals, normalMapUvs(0, straight, turned), kQuadIndices))
        EXPECT_NEAR(glm::dot(glm::vec3(t), glm::vec3(1, 0, 0)), 1.0f, 1e-5f);
}

} // namespace
} // namespace lumar
