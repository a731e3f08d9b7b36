// Where each phantom shape lands on its marker (app/phantom_model.h): a box exactly as before
// shapes existed (centred on offset, sides along the marker's axes), a plane in the marker
// plane, a cylinder with its axis along the marker's normal, heading turning each about that
// normal, a mesh fitted like an object; every phantom gets one material of its colour.
#include <algorithm>
#include <cmath>
#include <limits>

#include <glm/gtc/matrix_transform.hpp>
#include <gtest/gtest.h>

#include "gles_renderer/assets/builtin_shapes.h"
#include "phantom_model.h"

namespace lumar {
namespace {

struct Box {
    glm::dvec3 lo{std::numeric_limits<double>::infinity()};
    glm::dvec3 hi{-std::numeric_limits<double>::infinity()};
};

// The marker-frame bounds of the placed vertices.
Box placedBounds(const PhantomModel& placed)
{
    Box box;
    for (const GltfPrimitive& p : placed.model.primitives)
        for (const glm::vec3& v : p.positions) {
            const glm::dvec3 x(placed.markerFromModel * glm::dmat4(p.modelFromMesh) * glm::dvec4(glm::dvec3(v), 1.0));
            box.lo = glm::min(box.lo, x);
            box.hi = glm::max(box.hi, x);
        }
    return box;
}

void expectNear(const glm::dvec3& a, const glm::dvec3& b, double tolerance = 1e-6)
{
    for (int i = 0; i < 3; ++i)
        EXPECT_NEAR(a[i], b[i], tolerance) << "component " << i;
}

PhantomConfig phantom(const std::string& shape, const glm::dvec3& size, const glm::dvec3& offset)
{
    PhantomConfig p;
    p.name = "p";
    p.shape = shape;
    p.size = size;
    p.offset = offset;
    p.color = glm::dvec3(0.4, 0.3, 0.2);
    return p;
}

TEST(PhantomModel, BoxIsPlacedExactlyAsBefore)
{
    const PhantomConfig table = phantom("box", {1.2, 0.8, 0.02}, {0.0, 0.0, -0.0101});
    const PhantomModel placed = makePhantomModel(table);
    const glm::dmat4 before = glm::translate(glm::dmat4(1.0), table.offset) * glm::scale(glm::dmat4(1.0), table.size);
    EXPECT_EQ(placed.markerFromModel, before);
    ASSERT_EQ(placed.model.materials.size(), 1u);
    EXPECT_EQ(placed.model.materials[0].baseColorFactor, glm::vec4(0.4f, 0.3f, 0.2f, 1.0f));
    EXPECT_EQ(placed.model.materials[0].roughnessFactor, 1.0f);
    EXPECT_EQ(placed.model.materials[0].metallicFactor, 0.0f);
}

TEST(PhantomModel, PlaneLiesInTheMarkerPlaneFacingUp)
{
    const PhantomModel placed = makePhantomModel(phantom("plane", {1.2, 0.8, 5.0}, {0.1, 0.0, -0.001}));
    const Box box = placedBounds(placed);
    expectNear(box.lo, {-0.5, -0.4, -0.001});
    expectNear(box.hi, {0.7, 0.4, -0.001});
    const glm::dvec3 up = glm::dmat3(placed.markerFromModel) * glm::dvec3(placed.model.primitives[0].normals[0]);
    expectNear(glm::normalize(up), {0.0, 0.0, 1.0});
    EXPECT_TRUE(placed.model.materials[0].doubleSided);
}

TEST(PhantomModel, CylinderStandsOnItsAxisAlongTheNormal)
{
    const PhantomModel placed = makePhantomModel(phantom("cylinder", {0.08, 0.08, 0.12}, {0.0, 0.1, 0.06}));
    const Box box = placedBounds(placed);
    expectNear(box.lo, {-0.04, 0.06, 0.0});
    expectNear(box.hi, {0.04, 0.14, 0.12});
}

TEST(PhantomModel, HeadingTurnsAboutTheMarkerNormal)
{
    PhantomConfig turned = phantom("box", {0.4, 0.1, 0.2}, {0.0, 0.0, 0.1});
    turned.headingDeg = 90.0;
    const Box box = placedBounds(makePhantomModel(turned));
    expectNear(box.lo, {-0.05, -0.2, 0.0});
    expectNear(box.hi, {0.05, 0.2, 0.2});
}

TEST(PhantomModel, MeshIsFittedLikeAnObject)
{
    PhantomConfig mug = phantom("mesh", glm::dvec3(0.3), {0.1, 0.0, 0.0});
    GltfModel cube = makeCube();
    for (glm::vec3& v : cube.primitives[0].positions)
        v *= glm::vec3(2.0f, 1.0f, 1.0f); // 2 x 1 x 1, +Y up
    cube.boundsMin = glm::vec3(-1.0f, -0.5f, -0.5f);
    cube.boundsMax = glm::vec3(1.0f, 0.5f, 0.5f);
    cube.materials[0].doubleSided = true;
    mug.mesh = std::make_shared<const GltfModel>(cube);
    const PhantomModel placed = makePhantomModel(mug);
    const Box box = placedBounds(placed);
    // The longest side fits `size`; it stands on the marker plane, centred on the offset.
    expectNear(box.lo, {-0.05, -0.075, 0.0});
    expectNear(box.hi, {0.25, 0.075, 0.15});
    ASSERT_EQ(placed.model.materials.size(), 1u);
    EXPECT_TRUE(placed.model.materials[0].doubleSided);
    EXPECT_EQ(placed.model.materials[0].baseColorFactor, glm::vec4(0.4f, 0.3f, 0.2f, 1.0f));
}

} // namespace
} // namespace lumar
