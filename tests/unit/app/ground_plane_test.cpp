// The receiver-only ground under a marker's objects (app/ground_plane.h): on the marker's
// plane, centred under the footprint, reaching three object heights beyond it, and left out
// where a phantom's top already is that plane.
#include <gtest/gtest.h>

#include "ground_plane.h"

namespace lumar {
namespace {

// A 0.1 x 0.2 x 0.05 box standing on the marker at (0.3, 0.1).
PlacedBox standingBox()
{
    PlacedBox box;
    box.boundsMin = {-0.05f, -0.1f, 0.0f};
    box.boundsMax = {0.05f, 0.1f, 0.05f};
    box.markerFromModel[3] = glm::dvec4(0.3, 0.1, 0.0, 1.0);
    return box;
}

TEST(GroundPlane, LiesUnderTheFootprintAndReachesBeyondIt)
{
    const PlacedBox boxes[] = {standingBox()};
    const std::optional<glm::dmat4> ground = groundUnder(boxes, {});
    ASSERT_TRUE(ground);
    // The quad's corners on the marker plane.
    const glm::dvec3 low(*ground * glm::dvec4(-0.5, -0.5, 0.0, 1.0));
    const glm::dvec3 high(*ground * glm::dvec4(0.5, 0.5, 0.0, 1.0));
    EXPECT_DOUBLE_EQ(low.z, 0.0);
    EXPECT_DOUBLE_EQ(high.z, 0.0);
    EXPECT_NEAR(0.5 * (low.x + high.x), 0.3, 1e-9);
    EXPECT_NEAR(0.5 * (low.y + high.y), 0.1, 1e-7);
    // Reach: max(footprint's longest side 0.2, 3 heights 0.15) = 0.2 on each side.
    EXPECT_NEAR(high.x - low.x, 0.1 + 0.4, 1e-7);
    EXPECT_NEAR(high.y - low.y, 0.2 + 0.4, 1e-7);
    // Facing up, not mirrored.
    EXPECT_GT(glm::determinant(glm::dmat3(*ground)), 0.0);
}

TEST(GroundPlane, LeftOutWhereAPhantomTopIsTheMarkerPlane)
{
    const PlacedBox boxes[] = {standingBox()};
    PhantomConfig table;
    table.size = {1.2, 0.8, 0.02};
    table.offset = {0.0, 0.0, -0.0101}; // top 0.1 mm below the plane (daemon/assets/scenes/car.toml)
    EXPECT_FALSE(groundUnder(boxes, {&table, 1}));
    PhantomConfig cup; // a real object standing beside: not the floor
    cup.size = {0.1, 0.1, 0.1};
    cup.offset = {-0.3, 0.0, 0.05};
    EXPECT_TRUE(groundUnder(boxes, {&cup, 1}));
    PhantomConfig lowerShelf = table; // a surface 5 cm below the marker's plane
    lowerShelf.offset.z = -0.06;
    EXPECT_TRUE(groundUnder(boxes, {&lowerShelf, 1}));
    EXPECT_FALSE(groundUnder({}, {}));
}

// A table given as a plane phantom lying in the marker's plane is that plane too (a second
// receiver there would fight it for depth and darken twice: striped shadows).
TEST(GroundPlane, LeftOutOverAPlanePhantomInTheMarkerPlane)
{
    const PlacedBox boxes[] = {standingBox()};
    PhantomConfig table;
    table.shape = "plane";
    table.size = {1.2, 1.2, 1.0}; // z unused, as the config reader leaves it for [x, y]
    EXPECT_FALSE(groundUnder(boxes, {&table, 1}));
    table.offset.z = -0.06; // a surface below the marker's plane
    EXPECT_TRUE(groundUnder(boxes, {&table, 1}));
}

} // namespace
} // namespace lumar
