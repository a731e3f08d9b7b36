// The board profiles' GL quirks in the renderer's options (board/README.md): the
// software-renderer quirk picks the budget schedule for environment_maps = "auto", an explicit
// schedule wins, half-float-only reaches the IBL settings.
#include <gtest/gtest.h>

#include "config/config.h"
#include "pipeline.h"

namespace lumar {
namespace {

Config parse(const std::string& text)
{
    return parseConfig(text, "test.toml", ".");
}

TEST(BoardQuirks, SoftwareRendererPrefersTheBudgetSchedule)
{
    EXPECT_EQ(renderOptionsFor(parse("")).environmentMaps.policy, EnvironmentMapPolicy::EveryFrame);
    EXPECT_EQ(renderOptionsFor(parse("board = \"x86-uvc\"\n")).environmentMaps.policy,
              EnvironmentMapPolicy::EveryFrame);
    const RenderOptions qemu = renderOptionsFor(parse("board = \"qemu-virtual-board\"\n"));
    EXPECT_EQ(qemu.environmentMaps.policy, EnvironmentMapPolicy::Budget);
    EXPECT_TRUE(qemu.environmentMaps.dynamic);
    const RenderOptions chosen =
        renderOptionsFor(parse("board = \"qemu-virtual-board\"\n[rendering]\nenvironment_maps = \"every_frame\"\n"));
    EXPECT_EQ(chosen.environmentMaps.policy, EnvironmentMapPolicy::EveryFrame);
    EXPECT_FALSE(renderOptionsFor(parse("[rendering]\nenvironment_maps = \"off\"\n")).environmentMaps.dynamic);
}

TEST(BoardQuirks, HalfFloatOnlyReachesTheIblSettings)
{
    EXPECT_FALSE(renderOptionsFor(parse("")).environmentMaps.ibl.halfFloatOnly);
    EXPECT_TRUE(renderOptionsFor(parse("board = \"imx8mp\"\n")).environmentMaps.ibl.halfFloatOnly);
}

} // namespace
} // namespace lumar
