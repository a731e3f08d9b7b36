// [[lights]] and [shadows] (DESIGN.md §6.5): defaults, values, and every bad value as an
// InputError naming the file, the line and the key.
#include <gtest/gtest.h>

#include "config/config.h"
#include "config_fixture.h"

namespace lumar {
namespace {

class ShadowsConfigTest : public test::ConfigFixture {};

TEST_F(ShadowsConfigTest, Defaults)
{
    const Config c = parse("");
    EXPECT_TRUE(c.lights.empty());
    EXPECT_TRUE(c.shadows.enabled);
    EXPECT_EQ(c.shadows.mapSize, 1024);
    EXPECT_DOUBLE_EQ(c.shadows.softness, 1.5);
    EXPECT_TRUE(c.shadows.ground);
    EXPECT_EQ(c.shadows.resolution, "half");
}

TEST_F(ShadowsConfigTest, Values)
{
    const Config c =
        parse("[shadows]\nenabled = false\nmap_size = 2048\nsoftness = 3\nground = false\nresolution = \"quarter\"\n"
              "[[lights]]\ntype = \"directional\"\ndirection = [0, 3, 4]\ncolor = [1, 0.5, 0.25]\n"
              "intensity = 2.5\nshadow = false\n"
              "[[lights]]\ndirection = [1, 0, 0]\n");
    EXPECT_FALSE(c.shadows.enabled);
    EXPECT_EQ(c.shadows.mapSize, 2048);
    EXPECT_DOUBLE_EQ(c.shadows.softness, 3.0);
    EXPECT_FALSE(c.shadows.ground);
    EXPECT_EQ(c.shadows.resolution, "quarter");
    ASSERT_EQ(c.lights.size(), 2u);
    EXPECT_EQ(c.lights[0].type, "directional");
    EXPECT_NEAR(c.lights[0].direction.y, 0.6, 1e-12); // normalised
    EXPECT_NEAR(c.lights[0].direction.z, 0.8, 1e-12);
    EXPECT_DOUBLE_EQ(c.lights[0].color.g, 0.5);
    EXPECT_DOUBLE_EQ(c.lights[0].intensity, 2.5);
    EXPECT_FALSE(c.lights[0].shadow);
    EXPECT_TRUE(c.lights[1].shadow);
    EXPECT_DOUBLE_EQ(c.lights[1].intensity, 1.0);
    EXPECT_EQ(c.lights[1].color, glm::dvec3(1.0));
}

TEST_F(ShadowsConfigTest, BadShadowKeysNameTheLine)
{
    expectError("[shadows]\nmap_size = 128\n", "test.toml:2: shadows.map_size:");
    expectError("[shadows]\n\nmap_size = 8192\n", "test.toml:3: shadows.map_size:");
    expectError("[shadows]\nmap_size = 1000\n", "test.toml:2: shadows.map_size:");
    expectError("[shadows]\nsoftness = -1\n", "test.toml:2: shadows.softness:");
    expectError("[shadows]\nenabled = 1\n", "test.toml:2: shadows.enabled:");
    expectError("[shadows]\nground = \"yes\"\n", "test.toml:2: shadows.ground:");
    expectError("[shadows]\nresolution = \"double\"\n", "test.toml:2: shadows.resolution:");
    expectError("[shadows]\nresolution = 2\n", "test.toml:2: shadows.resolution:");
    expectError("[shadows]\nbias = 0.1\n", "test.toml:2: shadows.bias: unknown key");
}

TEST_F(ShadowsConfigTest, BadLightsNameTheLine)
{
    expectError("[[lights]]\ncolor = [1, 1, 1]\n", "test.toml:1: lights[0].direction:");
    expectError("[[lights]]\ndirection = [0, 0, 0]\n", "test.toml:2: lights[0].direction: must not be zero");
    expectError("[[lights]]\ndirection = [0, nan, 1]\n", "test.toml:2: lights[0].direction:");
    expectError("[[lights]]\ndirection = [0, 1]\n", "test.toml:2: lights[0].direction:");
    expectError("[[lights]]\ndirection = [0, 0, 1]\ntype = \"point\"\n", "test.toml:3: lights[0].type:");
    expectError("[[lights]]\ndirection = [0, 0, 1]\ncolor = [1.5, 1, 1]\n", "test.toml:3: lights[0].color:");
    expectError("[[lights]]\ndirection = [0, 0, 1]\nintensity = -1\n", "test.toml:3: lights[0].intensity:");
    expectError("[[lights]]\ndirection = [0, 0, 1]\nintensity = inf\n", "test.toml:3: lights[0].intensity:");
    expectError("[[lights]]\ndirection = [0, 0, 1]\nshadow = 1\n", "test.toml:3: lights[0].shadow:");
    expectError("[[lights]]\ndirection = [0, 0, 1]\nradius = 1\n", "test.toml:3: lights[0].radius: unknown key");
}

} // namespace
} // namespace lumar
