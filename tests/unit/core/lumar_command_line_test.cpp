// lumar's command line in-process: --help on stdout with exit 0, misuse as exit 2 with one
// line on stderr naming the command and what is wrong, values in both accepted forms.
#include <algorithm>
#include <string>
#include <utility>
#include <vector>

#include <gtest/gtest.h>

#include "lumar_command_line.h"

namespace lumar {
namespace {

struct Outcome {
    int exitCode;
    std::string out, err;
};

Outcome lumar(const std::vector<std::string>& args)
{
    testing::internal::CaptureStdout();
    testing::internal::CaptureStderr();
    const int exitCode = lumarMain(args);
    std::string out = testing::internal::GetCapturedStdout();
    return {exitCode, out, testing::internal::GetCapturedStderr()};
}

TEST(LumarCommandLine, HelpListsEveryOptionOnStdout)
{
    const std::vector<std::pair<std::string, std::vector<std::string>>> commands = {
        {"render", {"--config", "--frames", "--out", "--trace", "--log-level"}},
        {"run", {"--config", "--frames", "--log-level"}},
        {"check-config", {"FILE"}},
        {"detect", {"--tag-size", "--calib", "--family", "--decimate", "--log-level", "IMAGE"}},
        {"bench", {"--config", "--frames", "--warmup", "--json", "--no-profile", "--sync-detection", "--log-level"}},
        {"probe", {"--device"}},
        {"calibrate", {"--images", "--board", "--square", "--out", "--log-level"}},
    };
    for (const auto& [command, options] : commands) {
        const Outcome r = lumar({command, "--help"});
        EXPECT_EQ(r.exitCode, 0) << command;
        EXPECT_EQ(r.out.rfind("usage: lumar " + command, 0), 0u) << r.out;
        EXPECT_EQ(r.err, "");
        for (const std::string& option : options)
            EXPECT_NE(r.out.find(option), std::string::npos) << command << " " << option;
    }
    const Outcome top = lumar({"--help"});
    EXPECT_EQ(top.exitCode, 0);
    for (const auto& [command, options] : commands)
        EXPECT_NE(top.out.find("\n  " + command + " "), std::string::npos) << command;
    EXPECT_EQ(lumar({"help"}).out, top.out);
    EXPECT_EQ(lumar({"render", "--frames", "0", "-h"}).exitCode, 0) << "help wins over a mistake beside it";
}

TEST(LumarCommandLine, MisuseIsExitTwoWithOneLineNamingIt)
{
    const std::vector<std::pair<std::vector<std::string>, std::string>> cases = {
        {{}, "lumar: no command given (see 'lumar --help')"},
        {{"frobnicate"}, "lumar: unknown command 'frobnicate' (see 'lumar --help')"},
        {{"--frames", "3"}, "lumar: unknown option --frames (see 'lumar --help')"},
        {{"render"}, "lumar render: --out is required (see 'lumar render --help')"},
        {{"render", "--nope", "--out", "a.png"}, "lumar render: unknown option --nope (see 'lumar render --help')"},
        {{"render", "--out", "a.png", "b.png"},
         "lumar render: unexpected argument 'b.png' (see 'lumar render --help')"},
        {{"render", "--frames", "0", "--out", "a.png"}, "lumar render: --frames: 0 is outside [1, 1000000]"},
        {{"render", "--frames=12x", "--out=a.png"}, "lumar render: --frames: '12x' is not an integer"},
        {{"render", "--frames", "1", "--frames", "2", "--out", "a.png"}, "lumar render: --frames"},
        {{"render", "--out"}, "lumar render: --out"},
        {{"bench", "--json=yes"}, "lumar bench: "},
        {{"run", "--frames", "-1"}, "lumar run: "},
        {{"check-config"}, "lumar check-config: FILE is required"},
        {{"check-config", "a.toml", "b.toml"}, "lumar check-config: unexpected argument 'b.toml'"},
        {{"detect", "x.png"}, "lumar detect: --tag-size is required"},
        {{"detect", "--tag-size", "0.16"}, "lumar detect: IMAGE is required"},
        {{"detect", "--tag-size", "0.16", "--decimate", "9", "x.png"}, "lumar detect: --decimate: 9 is outside [1, 8]"},
        {{"detect", "--tag-size", "0.16", "--log-level", "loud", "x.png"}, "lumar detect: bad log level 'loud'"},
        {{"calibrate", "--images", "d", "--board", "9y6", "--square", "0.02", "--out", "c.yaml"},
         "lumar calibrate: --board: '9y6' is not COLSxROWS"},
        {{"calibrate", "--images", "d", "--board", "2x6", "--square", "0.02", "--out", "c.yaml"},
         "lumar calibrate: --board: 2x6: each side needs 3..100 inner corners"},
        {{"calibrate", "--images", "d", "--board", "9x6", "--square", "0", "--out", "c.yaml"},
         "lumar calibrate: --square: 0 is outside (0, 1000]"},
        {{"calibrate", "--board", "9x6", "--square", "0.02", "--out", "c.yaml"},
         "lumar calibrate: --images is required"},
        {{"probe", "--device"}, "lumar probe: --device"},
    };
    for (const auto& [args, starts] : cases) {
        const Outcome r = lumar(args);
        std::string line;
        for (const std::string& a : args)
            line += a + " ";
        EXPECT_EQ(r.exitCode, 2) << line;
        EXPECT_EQ(r.err.rfind(starts, 0), 0u) << line << "\n" << r.err;
        EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << line << "\n" << r.err;
        EXPECT_EQ(r.out, "") << line;
    }
}

TEST(LumarCommandLine, ValuesInBothFormsReachTheCommand)
{
    const std::string config = LUMAR_SOURCE_DIR "/daemon/assets/lumar.toml";
    const Outcome checked = lumar({"check-config", config});
    EXPECT_EQ(checked.exitCode, 0) << checked.err;
    EXPECT_EQ(checked.out, config + ": ok\n");

    // One JSON line per image; the tag size given both ways.
    const std::string photo = LUMAR_TEST_DATA_DIR "/apriltag/real/33369213973_9d9bb4cc96_c.jpg";
    const std::vector<std::pair<std::vector<std::string>, long>> runs = {
        {{"detect", "--tag-size=0.16", "--family=tag36h11", "--decimate=1", photo}, 1},
        {{"detect", "--tag-size", "0.16", "--family", "tag36h11", photo, photo}, 2},
    };
    for (const auto& [args, lines] : runs) {
        const Outcome r = lumar(args);
        EXPECT_EQ(r.exitCode, 0) << r.err;
        EXPECT_EQ(std::count(r.out.begin(), r.out.end(), '\n'), lines) << r.out;
        EXPECT_NE(r.out.find("\"detections\":[{"), std::string::npos) << r.out;
    }
}

} // namespace
} // namespace lumar
