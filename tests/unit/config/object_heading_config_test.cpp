// [[objects]] heading: read in degrees, validated like the other numbers (finite, within
// [-360, 360]), each error one line with its "FILE:LINE: key:" prefix.
#include <filesystem>

#include <gtest/gtest.h>

#include "config/config.h"
#include "config_fixture.h"

namespace lumar {
namespace {

class ObjectHeadingConfigTest : public test::ConfigFixture {};

const std::string kObject = "[[markers]]\nid = 0\nsize = 0.16\n[[objects]]\nmodel = \"box.glb\"\nmarker = 0\n";

TEST_F(ObjectHeadingConfigTest, DefaultsToZeroAndReadsDegrees)
{
    EXPECT_EQ(parse(kObject).objects[0].headingDeg, 0.0);
    EXPECT_DOUBLE_EQ(parse(kObject + "heading = 90\n").objects[0].headingDeg, 90.0);
    EXPECT_DOUBLE_EQ(parse(kObject + "heading = -137.5\n").objects[0].headingDeg, -137.5);
    const Config both = parse(kObject + "heading = 30.0\nrotation = [0.0, 0.0, 15.0]\n");
    EXPECT_DOUBLE_EQ(both.objects[0].headingDeg, 30.0);
    EXPECT_EQ(both.objects[0].rotationDeg, glm::dvec3(0.0, 0.0, 15.0));
}

TEST_F(ObjectHeadingConfigTest, BadValuesNameTheLine)
{
    expectError(kObject + "heading = \"north\"\n",
                "test.toml:7: objects[0].heading: expected a number, found a string");
    expectError(kObject + "heading = [0, 90]\n", "test.toml:7: objects[0].heading: expected a number");
    expectError(kObject + "heading = nan\n", "test.toml:7: objects[0].heading:");
    expectError(kObject + "heading = inf\n", "test.toml:7: objects[0].heading:");
    expectError(kObject + "heading = 400\n", "test.toml:7: objects[0].heading: 400 is outside [-360, 360]");
    expectError(kObject + "\nheading = -360.5\n", "test.toml:8: objects[0].heading:");
}

TEST_F(ObjectHeadingConfigTest, ShippedExampleShowsTheBuiltInDefaultsHeading)
{
    const Config example = loadConfig(std::filesystem::path(LUMAR_SOURCE_DIR) / "daemon/assets/lumar.toml");
    const Config builtIn = defaultConfig();
    ASSERT_EQ(example.objects.size(), builtIn.objects.size());
    for (size_t i = 0; i < example.objects.size(); ++i)
        EXPECT_EQ(example.objects[i].headingDeg, builtIn.objects[i].headingDeg);
}

TEST_F(ObjectHeadingConfigTest, PhantomsTurnByHeadingToo)
{
    // Phantoms turn about the marker's normal like objects (issue 15); no general rotation.
    const std::string phantom = "[[markers]]\nid = 0\nsize = 0.16\n[[phantoms]]\nmarker = 0\nsize = [1, 1, 1]\n";
    EXPECT_EQ(parse(phantom).phantoms[0].headingDeg, 0.0);
    EXPECT_DOUBLE_EQ(parse(phantom + "heading = 10\n").phantoms[0].headingDeg, 10.0);
    expectError(phantom + "heading = 400\n", "test.toml:7: phantoms[0].heading: 400 is outside [-360, 360]");
    expectError(phantom + "rotation = [0, 0, 10]\n", "test.toml:7: phantoms[0].rotation: unknown key");
}

} // namespace
} // namespace lumar
