// [[objects]] animation, loop, speed (issue 20): a name, an index, "all" or "none"; each
// error one line with its "FILE:LINE: key:" prefix. Names are checked against the model when
// it loads (tests/unit/app/object_animation_test.cpp).
#include <gtest/gtest.h>

#include "config/config.h"
#include "config_fixture.h"

namespace lumar {
namespace {

class ObjectAnimationConfigTest : public test::ConfigFixture {};

const std::string kObject = "[[markers]]\nid = 0\nsize = 0.16\n[[objects]]\nmodel = \"box.glb\"\nmarker = 0\n";

TEST_F(ObjectAnimationConfigTest, DefaultsPlayTheFirstClipLooping)
{
    const ObjectConfig object = parse(kObject).objects[0];
    EXPECT_EQ(object.animation, "");
    EXPECT_EQ(object.animationIndex, -1);
    EXPECT_TRUE(object.loop);
    EXPECT_EQ(object.speed, 1.0);
}

TEST_F(ObjectAnimationConfigTest, ReadsNamesIndicesLoopAndSpeed)
{
    EXPECT_EQ(parse(kObject + "animation = \"Walk\"\n").objects[0].animation, "Walk");
    EXPECT_EQ(parse(kObject + "animation = \"all\"\n").objects[0].animation, "all");
    EXPECT_EQ(parse(kObject + "animation = \"none\"\n").objects[0].animation, "none");
    const ObjectConfig indexed = parse(kObject + "animation = 2\nloop = false\nspeed = 0.5\n").objects[0];
    EXPECT_EQ(indexed.animationIndex, 2);
    EXPECT_FALSE(indexed.loop);
    EXPECT_EQ(indexed.speed, 0.5);
}

TEST_F(ObjectAnimationConfigTest, BadValuesNameTheLine)
{
    expectError(kObject + "animation = \"\"\n", "test.toml:7: objects[0].animation: must name an animation");
    expectError(kObject + "animation = -1\n", "test.toml:7: objects[0].animation:");
    expectError(kObject + "animation = 1.5\n", "test.toml:7: objects[0].animation: expected a string");
    expectError(kObject + "loop = 1\n", "test.toml:7: objects[0].loop:");
    expectError(kObject + "speed = -1\n", "test.toml:7: objects[0].speed:");
    expectError(kObject + "speed = nan\n", "test.toml:7: objects[0].speed:");
}

} // namespace
} // namespace lumar
