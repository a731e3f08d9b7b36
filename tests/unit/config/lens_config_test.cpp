// [rendering.lens] (DESIGN.md §6.5): defaults (off), values, and every bad value as an
// InputError naming the file, the line and the key.
#include <gtest/gtest.h>

#include "config/config.h"
#include "config_fixture.h"

namespace lumar {
namespace {

class LensConfigTest : public test::ConfigFixture {};

TEST_F(LensConfigTest, DefaultsAreOff)
{
    const Config c = parse("");
    EXPECT_FALSE(c.rendering.lens.enabled);
    EXPECT_EQ(c.rendering.lens, LensConfig{});
    EXPECT_EQ(parse("[rendering.lens]\n").rendering.lens, LensConfig{});
}

TEST_F(LensConfigTest, Values)
{
    const Config c = parse("[rendering.lens]\nenabled = true\nthreshold = 2.5\nbloom = false\nbloom_intensity = 0.8\n"
                           "bloom_radius = 64\nglare = true\nglare_streaks = 6\nglare_length = 200\n"
                           "glare_intensity = 0.1\nglare_angle = -45\n");
    const LensConfig& lens = c.rendering.lens;
    EXPECT_TRUE(lens.enabled);
    EXPECT_DOUBLE_EQ(lens.threshold, 2.5);
    EXPECT_FALSE(lens.bloom);
    EXPECT_DOUBLE_EQ(lens.bloomIntensity, 0.8);
    EXPECT_DOUBLE_EQ(lens.bloomRadius, 64.0);
    EXPECT_TRUE(lens.glare);
    EXPECT_EQ(lens.glareStreaks, 6);
    EXPECT_DOUBLE_EQ(lens.glareLength, 200.0);
    EXPECT_DOUBLE_EQ(lens.glareIntensity, 0.1);
    EXPECT_DOUBLE_EQ(lens.glareAngle, -45.0);
}

TEST_F(LensConfigTest, BadValuesNameTheLine)
{
    expectError("[rendering.lens]\nthreshold = -1\n", "test.toml:2: rendering.lens.threshold:");
    expectError("[rendering.lens]\nthreshold = nan\n", "test.toml:2: rendering.lens.threshold:");
    expectError("[rendering.lens]\n\nbloom_intensity = 17\n", "test.toml:3: rendering.lens.bloom_intensity:");
    expectError("[rendering.lens]\nbloom_radius = 1\n", "test.toml:2: rendering.lens.bloom_radius:");
    expectError("[rendering.lens]\nglare_streaks = 1\n", "test.toml:2: rendering.lens.glare_streaks:");
    expectError("[rendering.lens]\nglare_streaks = 17\n", "test.toml:2: rendering.lens.glare_streaks:");
    expectError("[rendering.lens]\nglare_length = 2000\n", "test.toml:2: rendering.lens.glare_length:");
    expectError("[rendering.lens]\nglare_intensity = -0.5\n", "test.toml:2: rendering.lens.glare_intensity:");
    expectError("[rendering.lens]\nglare_angle = 400\n", "test.toml:2: rendering.lens.glare_angle:");
    expectError("[rendering.lens]\nenabled = 1\n", "test.toml:2: rendering.lens.enabled:");
    expectError("[rendering.lens]\nstar = true\n", "test.toml:2: rendering.lens.star: unknown key");
}

} // namespace
} // namespace lumar
