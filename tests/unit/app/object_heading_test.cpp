// markerFromModel's heading and rotation (app/object_placement.h): heading turns an upright
// model about the marker's normal, rotation acts before it in the upright frame, and a
// turned model is set back on the plane.
#include <gtest/gtest.h>

#include "object_placement.h"

namespace lumar {
namespace {

constexpr double kTolerance = 1e-12;

glm::dvec3 transformPoint(const glm::dmat4& m, const glm::dvec3& p)
{
    return glm::dvec3(m * glm::dvec4(p, 1.0));
}

glm::dvec3 transformDirection(const glm::dmat4& m, const glm::dvec3& d)
{
    return glm::dmat3(m) * d;
}

void expectNear(const glm::dvec3& a, const glm::dvec3& b, double tolerance = kTolerance)
{
    EXPECT_NEAR(a.x, b.x, tolerance);
    EXPECT_NEAR(a.y, b.y, tolerance);
    EXPECT_NEAR(a.z, b.z, tolerance);
}

void expectMatrixNear(const glm::dmat4& a, const glm::dmat4& b)
{
    for (int c = 0; c < 4; ++c)
        for (int r = 0; r < 4; ++r)
            EXPECT_NEAR(a[c][r], b[c][r], kTolerance) << "column " << c << " row " << r;
}

// The lowest z of the model's bounding box placed by m.
double lowestCorner(const glm::dmat4& m, const glm::dvec3& lo, const glm::dvec3& hi)
{
    double lowest = 1e300;
    for (int corner = 0; corner < 8; ++corner) {
        const glm::dvec3 p(corner & 1 ? hi.x : lo.x, corner & 2 ? hi.y : lo.y, corner & 4 ? hi.z : lo.z);
        lowest = std::min(lowest, transformPoint(m, p).z);
    }
    return lowest;
}

// A car-like box: 2 wide (x), 1 high (y), 4 long (z), its origin off-centre.
const glm::vec3 kLo(-1.0f, 0.5f, -1.0f), kHi(1.0f, 1.5f, 3.0f);

TEST(ObjectHeading, NinetyDegreesTurnsModelXToMarkerY)
{
    ObjectConfig object;
    object.scale = 1.0;
    object.headingDeg = 90.0;
    const glm::dmat4 m = markerFromModel(object, kLo, kHi);
    expectNear(transformDirection(m, {1, 0, 0}), {0, 1, 0});
    // Still upright: model +Y along the normal; model +Z (towards -Y unturned) now towards +X.
    expectNear(transformDirection(m, {0, 1, 0}), {0, 0, 1});
    expectNear(transformDirection(m, {0, 0, 1}), {1, 0, 0});
    // Turned about its footprint's centre, which stays on the marker's origin, on the plane.
    expectNear(transformPoint(m, {0, 0.5, 1}), {0, 0, 0});
    EXPECT_NEAR(lowestCorner(m, kLo, kHi), 0.0, kTolerance);
}

TEST(ObjectHeading, IsCounterClockwiseSeenFromAbove)
{
    ObjectConfig object;
    object.headingDeg = 30.0;
    const glm::dvec3 x = transformDirection(markerFromModel(object, kLo, kHi), {1, 0, 0});
    expectNear(x, {std::cos(glm::radians(30.0)), std::sin(glm::radians(30.0)), 0.0});
    object.headingDeg = -30.0;
    EXPECT_LT(transformDirection(markerFromModel(object, kLo, kHi), {1, 0, 0}).y, 0.0);
}

TEST(ObjectHeading, ComposesWithOffsetAndSize)
{
    ObjectConfig object;
    object.size = 0.2; // the longest side, 4 model units, becomes 0.2 m
    object.headingDeg = 90.0;
    object.offset = {0.1, -0.05, 0.02};
    const glm::dmat4 m = markerFromModel(object, kLo, kHi);
    // The offset is in the marker frame, not turned by heading; the footprint centre lands on it.
    expectNear(transformPoint(m, {0, 0.5, 1}), object.offset);
    // The front (model +Z end, 2 units = 0.1 m from the centre) points along marker +X.
    expectNear(transformPoint(m, {0, 0.5, 3}), object.offset + glm::dvec3(0.1, 0, 0));
    EXPECT_NEAR(lowestCorner(m, kLo, kHi), object.offset.z, kTolerance);
}

TEST(ObjectHeading, AddsToARotationAboutTheNormal)
{
    ObjectConfig a, b, c;
    a.headingDeg = 50.0;
    a.rotationDeg = {0, 0, 20};
    b.headingDeg = 70.0;
    c.rotationDeg = {0, 0, 70};
    expectMatrixNear(markerFromModel(a, kLo, kHi), markerFromModel(b, kLo, kHi));
    expectMatrixNear(markerFromModel(a, kLo, kHi), markerFromModel(c, kLo, kHi));
}

TEST(ObjectHeading, RotationActsInTheUprightFrameBeforeHeading)
{
    // A model authored Z-up (its top along model +Z) is stood up by rotation = [-90, 0, 0]:
    // model +Z (marker -Y when upright) turns to marker +Z. Heading then turns it about the normal
    // and it keeps standing.
    ObjectConfig object;
    object.rotationDeg = {-90, 0, 0};
    expectNear(transformDirection(markerFromModel(object, kLo, kHi), {0, 0, 1}), {0, 0, 1});
    object.headingDeg = 90.0;
    const glm::dmat4 m = markerFromModel(object, kLo, kHi);
    expectNear(transformDirection(m, {0, 0, 1}), {0, 0, 1});
    expectNear(transformDirection(m, {1, 0, 0}), {0, 1, 0});
    // Lowest point (model z = -1) on the plane, the box centred on the origin.
    EXPECT_NEAR(lowestCorner(m, kLo, kHi), 0.0, kTolerance);
    expectNear(transformPoint(m, glm::dvec3(kLo + kHi) * 0.5), {0, 0, 2});
}

TEST(ObjectHeading, ATiltedModelIsSetBackOnThePlane)
{
    ObjectConfig object;
    object.rotationDeg = {0, 30, 0}; // about marker y: a sideways tilt
    object.offset = {0, 0, 0.05};
    const glm::dmat4 m = markerFromModel(object, kLo, kHi);
    EXPECT_NEAR(lowestCorner(m, kLo, kHi), 0.05, kTolerance);
    const glm::dvec3 centre = transformPoint(m, glm::dvec3(kLo + kHi) * 0.5);
    EXPECT_NEAR(centre.x, 0.0, kTolerance);
    EXPECT_NEAR(centre.y, 0.0, kTolerance);
    // The centre is half the tilted box's height up: the half width 1 (model x) tilted by
    // 30 degrees gives 1 sin 30, the half height 0.5 (model y) gives 0.5 cos 30.
    EXPECT_NEAR(centre.z - 0.05, 1.0 * std::sin(glm::radians(30.0)) + 0.5 * std::cos(glm::radians(30.0)), kTolerance);
}

TEST(ObjectHeading, ZeroHeadingAndRotationIsTheUprightPlacement)
{
    ObjectConfig object;
    object.scale = 0.5;
    const glm::dmat4 m = markerFromModel(object, kLo, kHi);
    // Bottom centre (0, 0.5, 1) on the origin, model +Y -> +Z, +X -> +X, +Z -> -Y.
    expectNear(transformPoint(m, {0, 0.5, 1}), {0, 0, 0});
    expectNear(transformDirection(m, {0, 1, 0}), {0, 0, 0.5});
    expectNear(transformDirection(m, {1, 0, 0}), {0.5, 0, 0});
    expectNear(transformDirection(m, {0, 0, 1}), {0, -0.5, 0});
}

} // namespace
} // namespace lumar
