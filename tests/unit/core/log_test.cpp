#include <gtest/gtest.h>

#include "core/log.h"

namespace lumar::log {
namespace {

TEST(Log, LevelsParseCaseInsensitively)
{
    Level l{};
    EXPECT_TRUE(parseLevel("DEBUG", l));
    EXPECT_EQ(l, Level::Debug);
    EXPECT_TRUE(parseLevel("warning", l));
    EXPECT_EQ(l, Level::Warn);
    EXPECT_FALSE(parseLevel("loud", l));
}

TEST(Log, SpecSetsPerCategoryLevels)
{
    ASSERT_TRUE(configure("*:warn,capture:debug"));
    EXPECT_TRUE(categories::Capture.enabled(Level::Debug));
    EXPECT_FALSE(categories::Render.enabled(Level::Info));
    EXPECT_TRUE(categories::Render.enabled(Level::Warn));
    ASSERT_TRUE(configure("info"));
    EXPECT_FALSE(categories::Capture.enabled(Level::Debug));
    EXPECT_TRUE(categories::Render.enabled(Level::Info));
}

TEST(Log, BadSpecChangesNothing)
{
    ASSERT_TRUE(configure("info"));
    EXPECT_FALSE(configure("capture:debug,render:loud"));
    EXPECT_FALSE(categories::Capture.enabled(Level::Debug));
    EXPECT_FALSE(configure("nosuchcategory:debug"));
}

} // namespace
} // namespace lumar::log
