#include <gtest/gtest.h>

#include "core/environment_frame.h"
#include "object_placement.h"

namespace lumar {
namespace {

glm::dvec3 transformPoint(const glm::dmat4& m, const glm::dvec3& p)
{
    return glm::dvec3(m * glm::dvec4(p, 1.0));
}

void expectNear(const glm::dvec3& a, const glm::dvec3& b, double tolerance = 1e-12)
{
    EXPECT_NEAR(a.x, b.x, tolerance);
    EXPECT_NEAR(a.y, b.y, tolerance);
    EXPECT_NEAR(a.z, b.z, tolerance);
}

TEST(ObjectPlacement, StandsTheModelOnTheMarker)
{
    ObjectConfig object;
    object.size = 0.2; // longest side (model y: 4 units) becomes 0.2 m
    const glm::vec3 lo(-1, 2, -0.5), hi(1, 6, 0.5);
    const glm::dmat4 m = markerFromModel(object, lo, hi);
    // Bottom centre of the box lands on the marker origin; model +Y is marker +Z.
    expectNear(transformPoint(m, {0, 2, 0}), {0, 0, 0});
    expectNear(transformPoint(m, {0, 6, 0}), {0, 0, 0.2});
    // Model +X stays marker +X; model +Z (glTF "front") faces marker -Y.
    expectNear(transformPoint(m, {1, 2, 0}), {0.05, 0, 0});
    expectNear(transformPoint(m, {0, 2, 0.5}), {0, -0.025, 0});
}

TEST(ObjectPlacement, OffsetRotationAndScale)
{
    ObjectConfig object;
    object.scale = 2.0;
    object.offset = {0.1, 0.0, 0.0};
    object.rotationDeg = {0, 0, 90}; // about the marker's up axis
    const glm::dmat4 m = markerFromModel(object, glm::vec3(-1), glm::vec3(1));
    // The box's bottom centre (0,-1,0) goes to the offset; model +X turns to marker +Y.
    expectNear(transformPoint(m, {0, -1, 0}), {0.1, 0, 0});
    expectNear(transformPoint(m, {1, -1, 0}), {0.1, 2.0, 0});
}

TEST(ObjectPlacement, EnvironmentUpIsMarkerUp)
{
    const glm::dmat3 r = environmentFromMarker();
    expectNear(r * glm::dvec3(0, 0, 1), {0, 1, 0});
    expectNear(r * glm::dvec3(1, 0, 0), {1, 0, 0});
}

} // namespace
} // namespace lumar
