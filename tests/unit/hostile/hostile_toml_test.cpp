// TOML and configuration values a hostile or careless file may hold (issue 16): each used to
// crash lumar (stack overflow, UBSan) or was accepted although meaningless.
#include <filesystem>
#include <string>

#include <gtest/gtest.h>

#include "config/board_profile.h"
#include "config/config.h"
#include "config/material_sidecar.h"
#include "config/toml_parse.h"
#include "hostile_support.h"
#include "unit/config/config_fixture.h"
#include "unit/render/render_test_support.h"

namespace lumar::test {
namespace {

class HostileToml : public ConfigFixture {};

TEST_F(HostileToml, DeeplyDottedKeyIsRefusedBeforeParsing)
{
    const std::string deep = repeat("a.", 5000) + "b = 1\n";
    expectRejected([&] { (void)parse(deep); }, "test.toml:1: ", "nested deeper than 32 levels");
}

TEST_F(HostileToml, DeepTableHeaderIsRefused)
{
    expectRejected([&] { (void)parse("log_level = \"info\"\n[" + repeat("t.", 4000) + "u]\n"); },
                   "test.toml:2: ", "nested deeper than");
    expectRejected([&] { (void)parse("[[" + repeat("t.", 4000) + "u]]\n"); }, "test.toml:1: ", "nested deeper than");
}

TEST_F(HostileToml, DeepInlineArraysAndTablesAreRefused)
{
    expectRejected([&] { (void)parse("a = " + repeat("[", 3000) + repeat("]", 3000) + "\n"); },
                   "test.toml:1: ", "nested deeper than");
    expectRejected([&] { (void)parse("a = " + repeat("{b = ", 3000) + "1" + repeat("}", 3000) + "\n"); },
                   "test.toml:1: ", "nested deeper than");
    // Arrays spanning lines, with comments, count the same way.
    expectRejected([&] { (void)parse("a = [\n" + repeat("[ # c\n", 100) + "]\n"); }, "test.toml:", "nested deeper");
}

TEST_F(HostileToml, NestingWithinTheLimitStillParses)
{
    // Depth is counted, not guessed from brackets in strings or comments.
    EXPECT_NO_THROW(checkTomlText("a = \"" + repeat("[{.", 500) + "\" # " + repeat("[", 500) + "\n" + "b = '''\n" +
                                      repeat("[[[.", 300) + "\n'''\nc = [[1, 2], [3]]\n",
                                  "ok.toml"));
    EXPECT_NO_THROW(checkTomlText("[" + repeat("t.", 20) + "u]\n" + repeat("k.", 5) + "v = [[1]]\n", "ok.toml"));
}

TEST_F(HostileToml, InvalidUtf8IsRefusedWithItsLine)
{
    for (const std::string bad : {"\xff", "\xc0\xaf", "\xed\xa0\x80", "\xf4\x90\x80\x80", "\xe2\x82"}) {
        expectRejected([&] { (void)parse("log_level = \"info\"\n\"k" + bad + "\" = 1\n"); },
                       "test.toml:2: ", "invalid UTF-8");
        expectRejected([&] { (void)parse("k" + bad + " = 1\n"); }, "test.toml:1: ", "invalid UTF-8");
    }
    EXPECT_NO_THROW(checkTomlText("\"caf\xc3\xa9 \xe2\x82\xac \xf0\x9f\x98\x80\" = 1\n", "ok.toml"));
}

TEST_F(HostileToml, OverlongKeyIsRefused)
{
    expectRejected([&] { (void)parse(std::string(5000, 'k') + " = 1\n"); }, "test.toml:1: ", "longer than 1024");
}

TEST_F(HostileToml, BoardProfileAndMaterialSidecarGoThroughTheSameGuard)
{
    expectRejected([&] { (void)parseBoardProfile("[" + repeat("board.", 3000) + "x]\n", "evil-board.toml"); },
                   "evil-board.toml:1: ", "nested deeper");
    expectRejected([&] { (void)parseBoardProfile("[board]\nna\xffme = 1\n", "evil-board.toml"); },
                   "evil-board.toml:2: ", "invalid UTF-8");
    const std::filesystem::path sidecar = dir_ / "evil.materials.toml";
    writeText(sidecar, "[material.\"x\"]\n" + repeat("e.", 3000) + "f = 1\n");
    expectRejected([&] { (void)loadMaterialSidecar(sidecar); }, sidecar.string() + ":2: ", "nested deeper");
}

TEST_F(HostileToml, HugeConfigFileIsRefused)
{
    const std::filesystem::path file = dir_ / "huge.toml";
    writeText(file, "# " + std::string(2 << 20, 'x') + "\n");
    expectRejected([&] { (void)loadConfig(file); }, file.string() + ": ", "larger than 1 MiB");
}

const char* const kObjectOnMarker = "[[markers]]\nid = 0\nsize = 0.1\n[[objects]]\nmodel = \"box.glb\"\nmarker = 0\n";

TEST_F(HostileToml, PlacementNumbersMustBeFiniteAndInRange)
{
    expectRejected([&] { (void)parse(std::string(kObjectOnMarker) + "offset = [1e308, 0, 0]\n"); },
                   "test.toml:7: objects[0].offset: ", "within [-100, 100]");
    expectRejected([&] { (void)parse(std::string(kObjectOnMarker) + "rotation = [0, 1e300, 0]\n"); },
                   "test.toml:7: objects[0].rotation: ", "within [-360, 360]");
    expectRejected([&] { (void)parse(std::string(kObjectOnMarker) + "offset = [-1e308, 0, 0]\n"); },
                   "test.toml:7: objects[0].offset: ", "within");
    expectRejected(
        [&] {
            (void)parse("[[markers]]\nid = 0\nsize = 0.1\n[[phantoms]]\nmarker = 0\nshape = \"box\"\n"
                        "size = [0.1, 0.1, 0.1]\noffset = [0, 0, 1e308]\n");
        },
        "test.toml:8: phantoms[0].offset: ", "within");
    expectRejected([&] { (void)parse("[[lights]]\ndirection = [1e300, 1e300, 0]\n"); },
                   "test.toml:2: lights[0].direction: ", "within");
    expectRejected(
        [&] { (void)parse("[[maps]]\nname = \"m\"\n[[maps.tags]]\nid = 1\nsize = 0.1\nrotation = [1e300, 0, 0]\n"); },
        "test.toml:6: maps[0].tags[0].rotation: ", "within [-360, 360]");
    // Ordinary values pass.
    EXPECT_NO_THROW((void)parse(std::string(kObjectOnMarker) + "offset = [0.1, -2, 3]\nrotation = [90, -360, 45]\n"));
}

TEST_F(HostileToml, ModeSizeDoesNotOverflow)
{
    for (const char* mode : {"4294967297x1", "1x4294967297", "2147483648x1080", "-1920x1080", "+1920x1080",
                             " 1920x1080", "1920x 1080", "16385x1", "x", "1920x"})
        expectRejected([&] { (void)parse(std::string("[output]\nmode = \"") + mode + "\"\n"); },
                       "test.toml:2: output.mode: ", "WIDTHxHEIGHT");
    EXPECT_EQ(parse("[output]\nmode = \"16384x1\"\n").output.mode, "16384x1");
}

} // namespace
} // namespace lumar::test
