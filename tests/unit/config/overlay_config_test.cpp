// [output] overlay (the setup view, issue 21): off by default, a boolean, and anything else an
// InputError naming the file, the line and the key.
#include <gtest/gtest.h>

#include "config/config.h"
#include "config_fixture.h"

namespace lumar {
namespace {

class OverlayConfigTest : public test::ConfigFixture {};

TEST_F(OverlayConfigTest, OffByDefault)
{
    EXPECT_FALSE(parse("").output.overlay);
    EXPECT_FALSE(parse("[output]\n").output.overlay);
}

TEST_F(OverlayConfigTest, OnWhenAskedFor)
{
    EXPECT_TRUE(parse("[output]\noverlay = true\n").output.overlay);
    EXPECT_FALSE(parse("[output]\noverlay = false\n").output.overlay);
}

TEST_F(OverlayConfigTest, ANonBooleanNamesTheLine)
{
    const std::string message = expectError("[output]\n\noverlay = \"yes\"\n", "test.toml:3");
    EXPECT_NE(message.find("overlay"), std::string::npos) << message;
}

} // namespace
} // namespace lumar
