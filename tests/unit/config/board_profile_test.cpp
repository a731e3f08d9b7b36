// Board profiles: every shipped board/*.toml parses and validates, errors carry the exact
// "FILE:LINE: key:" of the offending value, and a configuration's `board = "..."` supplies
// the [camera] defaults that its own [camera] table overrides.
#include <algorithm>
#include <filesystem>
#include <fstream>

#include <gtest/gtest.h>

#include "config/board_profile.h"
#include "config/config.h"
#include "core/error.h"

namespace lumar {
namespace {

namespace fs = std::filesystem;

const fs::path kBoardDir = fs::path(LUMAR_SOURCE_DIR) / "board";

// A valid profile, one key per line, so tests can replace a line and know its number.
const std::string kValid = "[board]\n"                         // 1
                           "name = \"test-board\"\n"           // 2
                           "[camera]\n"                        // 3
                           "source = \"v4l2\"\n"               // 4
                           "formats = [\"yuyv\"]\n"            // 5
                           "[display]\n"                       // 6
                           "plane = \"primary\"\n"             // 7
                           "connector = \"HDMI-A-1\"\n"        // 8
                           "[gl]\n"                            // 9
                           "quirks = [\"no-native-fence\"]\n"; // 10

std::string replaceLine(const std::string& text, int line, const std::string& replacement)
{
    size_t begin = 0;
    for (int i = 1; i < line; ++i)
        begin = text.find('\n', begin) + 1;
    const size_t end = text.find('\n', begin);
    return text.substr(0, begin) + replacement + text.substr(end);
}

// Parses `text` as board.toml, expects an InputError, returns its message.
std::string errorOf(const std::string& text)
{
    try {
        (void)parseBoardProfile(text, "board.toml");
    } catch (const InputError& e) {
        const std::string message = e.what();
        EXPECT_EQ(message.find('\n'), std::string::npos) << "one line: " << message;
        return message;
    }
    ADD_FAILURE() << "no error for:\n" << text;
    return {};
}

TEST(BoardProfileTest, EveryShippedBoardParsesAndValidates)
{
    std::vector<std::string> names;
    for (const auto& entry : fs::directory_iterator(kBoardDir)) {
        if (entry.path().extension() != ".toml")
            continue;
        SCOPED_TRACE(entry.path().string());
        const BoardProfile board = loadBoardProfile(entry.path());
        // The name is what a configuration's `board = "..."` looks up: the file's own name.
        EXPECT_EQ(board.name, entry.path().stem().string());
        EXPECT_FALSE(board.description.empty());
        EXPECT_FALSE(board.camera.formats.empty());
        EXPECT_TRUE(isBoardProfileFile(entry.path()));
        names.push_back(board.name);
    }
    std::sort(names.begin(), names.end());
    EXPECT_EQ(names, (std::vector<std::string>{"imx8mp", "qemu-virtual-board", "raspberry-pi-5", "x86-uvc"}));
    EXPECT_EQ(shippedBoardNames(), names);
}

TEST(BoardProfileTest, ShippedBoardsSayWhatTheirHardwareNeeds)
{
    const BoardProfile pi = loadBoardProfile(kBoardDir / "raspberry-pi-5.toml");
    EXPECT_EQ(pi.camera.source, "libcamera");
    EXPECT_EQ(pi.display.drmDrivers, std::vector<std::string>{"vc4"});
    EXPECT_EQ(pi.display.plane, "overlay");
    EXPECT_TRUE(pi.glQuirks.empty());

    const BoardProfile uvc = loadBoardProfile(kBoardDir / "x86-uvc.toml");
    EXPECT_EQ(uvc.camera.formats.front(), "mjpeg");
    EXPECT_EQ(uvc.camera.width, 1280);
    EXPECT_EQ(uvc.camera.height, 720);
    EXPECT_TRUE(uvc.display.drmDrivers.empty());

    const BoardProfile imx = loadBoardProfile(kBoardDir / "imx8mp.toml");
    EXPECT_TRUE(imx.hasQuirk("half-float-only"));
    EXPECT_FALSE(imx.hasQuirk("no-native-fence"));

    const BoardProfile qemu = loadBoardProfile(kBoardDir / "qemu-virtual-board.toml");
    EXPECT_EQ(qemu.camera.formats, std::vector<std::string>{"yuyv"});
    EXPECT_EQ(qemu.camera.width, 640);
    EXPECT_EQ(qemu.camera.height, 480);
    EXPECT_DOUBLE_EQ(qemu.camera.fps, 25.0);
    EXPECT_FALSE(qemu.display.modifiers);
    EXPECT_TRUE(qemu.hasQuirk("no-native-fence"));
}

TEST(BoardProfileTest, DefaultsForOptionalTables)
{
    const BoardProfile board = parseBoardProfile("[board]\nname = \"b\"\n[camera]\nsource = \"libcamera\"\n", "b.toml");
    EXPECT_EQ(board.camera.device, "auto");
    EXPECT_TRUE(board.camera.formats.empty());
    EXPECT_EQ(board.display.connector, "auto");
    EXPECT_EQ(board.display.plane, "primary");
    EXPECT_TRUE(board.display.modifiers);
    EXPECT_TRUE(board.glQuirks.empty());
    EXPECT_EQ(parseBoardProfile(kValid, "board.toml").display.connector, "HDMI-A-1");
}

TEST(BoardProfileTest, UnknownQuirkNamesItsLine)
{
    EXPECT_EQ(errorOf(replaceLine(kValid, 10, "quirks = [\"no-native-fence\",\n  \"fast-gpu\"]")),
              "board.toml:11: gl.quirks: 'fast-gpu' is not a known GL quirk (no-native-fence, half-float-only, "
              "no-dma-buf-import, software-renderer)");
}

TEST(BoardProfileTest, UnknownFormatNamesItsLine)
{
    EXPECT_EQ(errorOf(replaceLine(kValid, 5, "formats = [\"rgb24\"]")),
              "board.toml:5: camera.formats: 'rgb24' is not a camera format (nv12, yuyv, mjpeg, grey)");
    // libcamera's viewfinder stream has no MJPEG.
    EXPECT_EQ(errorOf(replaceLine(replaceLine(kValid, 4, "source = \"libcamera\""), 5, "formats = [\"mjpeg\"]")),
              "board.toml:5: camera.formats: 'mjpeg': libcamera delivers nv12, yuyv only");
    EXPECT_EQ(errorOf(replaceLine(kValid, 5, "formats = [\"yuyv\", \"yuyv\"]")),
              "board.toml:5: camera.formats: 'yuyv' is listed twice");
}

TEST(BoardProfileTest, BadPlaneNamesItsLine)
{
    EXPECT_EQ(errorOf(replaceLine(kValid, 7, "plane = \"cursor\"")),
              "board.toml:7: display.plane: 'cursor' is not one of primary, overlay");
}

TEST(BoardProfileTest, MissingBoardNameNamesTheTable)
{
    EXPECT_EQ(errorOf(replaceLine(kValid, 2, "description = \"no name\"")),
              "board.toml:1: board.name: required key is missing");
    EXPECT_EQ(errorOf("[camera]\nsource = \"v4l2\"\n"),
              "board.toml:1: board: required table [board] is missing (is this a board profile?)");
}

TEST(BoardProfileTest, OtherMistakesNameTheirLines)
{
    EXPECT_EQ(
        errorOf(replaceLine(kValid, 8, "connector = \"HDMI-1\"")).rfind("board.toml:8: display.connector: 'HDMI-1'", 0),
        0u);
    EXPECT_EQ(errorOf(replaceLine(kValid, 4, "source = \"v4l2\"\ndevice = \"video0\"")),
              "board.toml:5: camera.device: 'video0': a v4l2 camera is a device node in /dev");
    EXPECT_EQ(errorOf(replaceLine(kValid, 7, "plane = \"primary\"\nrotate = 90")),
              "board.toml:8: display.rotate: unknown key");
    EXPECT_EQ(errorOf(replaceLine(kValid, 2, "name = \"Test Board\"")),
              "board.toml:2: board.name: 'Test Board' must be lower-case letters, digits, '-' and '_'");
    EXPECT_EQ(errorOf(replaceLine(kValid, 10, "quirks = \"no-native-fence\"")),
              "board.toml:10: gl.quirks: expected an array of strings, found a string");
}

TEST(BoardProfileTest, CannotReadIsAnInputError)
{
    EXPECT_THROW((void)loadBoardProfile(kBoardDir / "no-such-board.toml"), InputError);
    EXPECT_FALSE(isBoardProfileFile(kBoardDir / "no-such-board.toml"));
    EXPECT_FALSE(isBoardProfileFile(fs::path(LUMAR_SOURCE_DIR) / "daemon/assets/lumar.toml"));
}

class BoardInConfigTest : public ::testing::Test {
protected:
    void SetUp() override
    {
        dir_ = fs::temp_directory_path() /
               ("lumar-board-" + std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()));
        fs::remove_all(dir_);
        fs::create_directories(dir_);
    }
    void TearDown() override { fs::remove_all(dir_); }

    fs::path dir_;
};

TEST_F(BoardInConfigTest, ShippedBoardSuppliesCameraDefaults)
{
    const Config c = parseConfig("board = \"x86-uvc\"\n", "test.toml", dir_);
    ASSERT_TRUE(c.board.has_value());
    EXPECT_EQ(c.board->name, "x86-uvc");
    EXPECT_EQ(c.camera.source, "v4l2");
    EXPECT_EQ(c.camera.format, "mjpeg");
    EXPECT_EQ(c.camera.width, 1280);
    EXPECT_EQ(c.camera.height, 720);
}

TEST_F(BoardInConfigTest, CameraTableOverridesTheBoard)
{
    const Config c =
        parseConfig("board = \"qemu-virtual-board\"\n[camera]\nwidth = 320\nformat = \"nv12\"\n", "test.toml", dir_);
    EXPECT_EQ(c.camera.source, "v4l2");
    EXPECT_EQ(c.camera.width, 320);  // the table's
    EXPECT_EQ(c.camera.height, 480); // the board's
    EXPECT_DOUBLE_EQ(c.camera.fps, 25.0);
    EXPECT_EQ(c.camera.format, "nv12");
}

TEST_F(BoardInConfigTest, BoardByPathAndItsErrors)
{
    std::ofstream(dir_ / "mine.toml") << replaceLine(kValid, 7, "plane = \"side\"");
    try {
        (void)parseConfig("board = \"mine.toml\"\n", "test.toml", dir_);
        ADD_FAILURE() << "no error";
    } catch (const InputError& e) {
        // The error is the board file's own, at its own line.
        EXPECT_EQ(std::string(e.what()),
                  (dir_ / "mine.toml").string() + ":7: display.plane: 'side' is not one of primary, overlay");
    }
    try {
        (void)parseConfig("log_level = \"info\"\nboard = \"atari-st\"\n", "test.toml", dir_);
        ADD_FAILURE() << "no error";
    } catch (const InputError& e) {
        EXPECT_EQ(std::string(e.what()).rfind("test.toml:2: board: no board profile ", 0), 0u) << e.what();
        EXPECT_NE(std::string(e.what()).find("(shipped: imx8mp, qemu-virtual-board, raspberry-pi-5, x86-uvc)"),
                  std::string::npos)
            << e.what();
    }
}

} // namespace
} // namespace lumar
