#include <gtest/gtest.h>

#include "command_line.h"

namespace lumar {
namespace {

const std::vector<OptionSpec> kSpecs = {{"frames"}, {"out", true, true}, {"json", false}};

TEST(CommandLine, ValuesFlagsAndPositionals)
{
    const CommandLine cl({"--frames", "12", "--out=a.png", "--out", "b.y4m", "--json", "x.jpg"}, kSpecs);
    EXPECT_EQ(cl.integer("frames", 0, 1, 100), 12);
    EXPECT_EQ(cl.values("out"), (std::vector<std::string>{"a.png", "b.y4m"}));
    EXPECT_TRUE(cl.has("json"));
    EXPECT_EQ(cl.positional(), std::vector<std::string>{"x.jpg"});
    EXPECT_FALSE(cl.helpRequested());
    EXPECT_EQ(cl.integer("missing", 7, 0, 10), 7);
}

TEST(CommandLine, MisuseIsAUsageError)
{
    EXPECT_THROW(CommandLine({"--nope"}, kSpecs), UsageError);
    EXPECT_THROW(CommandLine({"--frames"}, kSpecs), UsageError);
    EXPECT_THROW(CommandLine({"--frames", "1", "--frames", "2"}, kSpecs), UsageError);
    EXPECT_THROW(CommandLine({"--json=yes"}, kSpecs), UsageError);
    EXPECT_THROW((void)CommandLine({"--frames", "12x"}, kSpecs).integer("frames", 0, 0, 100), UsageError);
    EXPECT_THROW((void)CommandLine({"--frames", "500"}, kSpecs).integer("frames", 0, 0, 100), UsageError);
    EXPECT_TRUE(CommandLine({"-h"}, kSpecs).helpRequested());
}

} // namespace
} // namespace lumar
