// Parsing and validation of board profiles (board_profile.h) through the configuration's
// TableReader, so a board file's errors read exactly like a configuration's.
#include "config/board_profile.h"

#include <algorithm>
#include <array>

#include "config/config.h"
#include "config/toml_parse.h"
#include "config/toml_reader.h"
#include "core/error.h"
#include "core/file_bytes.h"
#include "core/log.h"

namespace lumar {
namespace {

using config_detail::TableReader;

// A board file is a page of text; anything bigger is not one.
constexpr uintmax_t kMaxBoardFileBytes = 1 << 20;

constexpr std::array<std::string_view, 4> kGlQuirks = {"no-native-fence", "half-float-only", "no-dma-buf-import",
                                                       "software-renderer"};

// The [camera] format names (config.cpp) other than "auto": a profile lists real formats.
constexpr std::array<std::string_view, 4> kFormats = {"nv12", "yuyv", "mjpeg", "grey"};
// libcamera's viewfinder stream is delivered in these only (capture/libcamera).
constexpr std::array<std::string_view, 2> kLibcameraFormats = {"nv12", "yuyv"};

// DRM connector type names as the kernel prints them (drm_connector_enum_list), each
// followed by "-N" in a connector name.
constexpr std::array<std::string_view, 21> kConnectorTypes = {
    "Unknown", "VGA",    "DVI-I", "DVI-D", "DVI-A",   "Composite", "SVIDEO", "LVDS",      "Component", "DIN", "DP",
    "HDMI-A",  "HDMI-B", "TV",    "eDP",   "Virtual", "DSI",       "DPI",    "Writeback", "SPI",       "USB"};

template <size_t N> bool contains(const std::array<std::string_view, N>& list, std::string_view value)
{
    return std::find(list.begin(), list.end(), value) != list.end();
}

template <size_t N> std::string joined(const std::array<std::string_view, N>& list)
{
    std::string text;
    for (std::string_view item : list)
        text += (text.empty() ? "" : ", ") + std::string(item);
    return text;
}

// "HDMI-A-1": a known connector type, a dash, a positive decimal number.
bool isConnectorName(std::string_view name)
{
    const size_t dash = name.rfind('-');
    if (dash == std::string_view::npos || dash + 1 == name.size())
        return false;
    const std::string_view number = name.substr(dash + 1);
    if (number.front() == '0' ||
        !std::all_of(number.begin(), number.end(), [](char c) { return c >= '0' && c <= '9'; }))
        return false;
    return contains(kConnectorTypes, name.substr(0, dash));
}

// Names: lower-case letters, digits, '-' and '_' (board names double as file names; DRM
// driver names are of this form).
bool isPlainName(std::string_view name)
{
    return !name.empty() && std::all_of(name.begin(), name.end(), [](char c) {
        return (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '-' || c == '_';
    });
}

// An array of strings, each checked by `check` (which returns what is wrong, or "");
// duplicates are errors. A failure names the line of the offending element.
template <typename Check> std::vector<std::string> readStringList(TableReader& r, std::string_view key, Check&& check)
{
    std::vector<std::string> values;
    for (const auto& [value, node] : r.stringArray(key)) {
        if (const std::string what = check(value); !what.empty())
            r.fail(node, key, what);
        if (std::find(values.begin(), values.end(), value) != values.end())
            r.fail(node, key, "'" + value + "' is listed twice");
        values.push_back(value);
    }
    return values;
}

void readBoard(TableReader& root, BoardProfile& board)
{
    const toml::table* table = root.table("board");
    if (!table)
        root.fail(nullptr, "board", "required table [board] is missing (is this a board profile?)");
    TableReader r(*table, "board", root.fileName());
    if (!r.has("name"))
        r.failMissing("name");
    r.string("name", board.name);
    if (!isPlainName(board.name))
        r.fail(r.node("name"), "name", "'" + board.name + "' must be lower-case letters, digits, '-' and '_'");
    r.string("description", board.description);
    r.finish();
}

void readCamera(TableReader& root, BoardCameraProfile& camera)
{
    const toml::table* table = root.table("camera");
    if (!table)
        root.fail(nullptr, "camera", "required table [camera] is missing");
    TableReader r(*table, "camera", root.fileName());
    if (!r.has("source"))
        r.failMissing("source");
    r.oneOf("source", camera.source, {"v4l2", "libcamera"});
    if (camera.source == "libcamera")
        camera.device = "auto";
    r.string("device", camera.device);
    if (camera.device.empty())
        r.fail(r.node("device"), "device", "must not be empty");
    if (camera.source == "v4l2" && !camera.device.starts_with("/dev/"))
        r.fail(r.node("device"), "device", "'" + camera.device + "': a v4l2 camera is a device node in /dev");
    const bool libcamera = camera.source == "libcamera";
    camera.formats = readStringList(r, "formats", [&](const std::string& format) -> std::string {
        if (!contains(kFormats, format))
            return "'" + format + "' is not a camera format (" + joined(kFormats) + ")";
        if (libcamera && !contains(kLibcameraFormats, format))
            return "'" + format + "': libcamera delivers " + joined(kLibcameraFormats) + " only";
        return {};
    });
    r.integer("width", camera.width, 16, 8192);
    r.checkEven("width", camera.width);
    r.integer("height", camera.height, 16, 8192);
    r.checkEven("height", camera.height);
    r.number("fps", camera.fps, 0.0, 240.0, true);
    r.finish();
}

void readDisplay(TableReader& root, BoardDisplayProfile& display)
{
    const toml::table* table = root.table("display");
    if (!table)
        return;
    TableReader r(*table, "display", root.fileName());
    display.drmDrivers = readStringList(r, "drm_drivers", [](const std::string& driver) -> std::string {
        if (!isPlainName(driver))
            return "'" + driver + "' is not a DRM driver name (lower-case letters, digits, '-' and '_')";
        return {};
    });
    r.string("connector", display.connector);
    if (display.connector != "auto" && !isConnectorName(display.connector))
        r.fail(r.node("connector"), "connector",
               "'" + display.connector + "' is neither \"auto\" nor a DRM connector name such as HDMI-A-1 (" +
                   joined(kConnectorTypes) + ", then -N)");
    r.oneOf("plane", display.plane, {"primary", "overlay"});
    r.boolean("modifiers", display.modifiers);
    r.finish();
}

void readGl(TableReader& root, std::vector<std::string>& quirks)
{
    const toml::table* table = root.table("gl");
    if (!table)
        return;
    TableReader r(*table, "gl", root.fileName());
    quirks = readStringList(r, "quirks", [](const std::string& quirk) -> std::string {
        if (!contains(kGlQuirks, quirk))
            return "'" + quirk + "' is not a known GL quirk (" + joined(kGlQuirks) + ")";
        return {};
    });
    r.finish();
}

} // namespace

bool BoardProfile::hasQuirk(std::string_view quirk) const
{
    return std::find(glQuirks.begin(), glQuirks.end(), quirk) != glQuirks.end();
}

std::span<const std::string_view> knownGlQuirks()
{
    return kGlQuirks;
}

BoardProfile parseBoardProfile(std::string_view text, const std::filesystem::path& fileName)
{
    const std::string name = fileName.string();
    const toml::table root = parseToml(text, name);
    BoardProfile board;
    board.sourceFile = fileName;
    TableReader r(root, "", name);
    readBoard(r, board);
    readCamera(r, board.camera);
    readDisplay(r, board.display);
    readGl(r, board.glQuirks);
    r.finish();
    return board;
}

BoardProfile loadBoardProfile(const std::filesystem::path& file)
{
    std::vector<uint8_t> bytes;
    try {
        bytes = readFileBytes(file, kMaxBoardFileBytes);
    } catch (const InputError& e) {
        throw InputError(file.string() + ": cannot read: " + e.what());
    }
    BoardProfile board =
        parseBoardProfile(std::string_view(reinterpret_cast<const char*>(bytes.data()), bytes.size()), file);
    LUMAR_LOG(Config, Debug) << "loaded board profile " << board.name << " from " << file.string();
    return board;
}

bool isBoardProfileFile(const std::filesystem::path& file)
{
    try {
        const std::vector<uint8_t> bytes = readFileBytes(file, kMaxBoardFileBytes);
        const toml::table root =
            parseToml(std::string_view(reinterpret_cast<const char*>(bytes.data()), bytes.size()), file.string());
        const toml::node* board = root.get("board");
        return board != nullptr && board->is_table();
    } catch (const InputError&) {
        return false;
    }
}

std::filesystem::path boardDirectory()
{
    std::error_code ec;
    const std::filesystem::path installed = assetDirectory() / "board";
    if (std::filesystem::is_directory(installed, ec))
        return installed;
    return std::filesystem::path(LUMAR_SOURCE_BOARD_DIR).lexically_normal();
}

std::vector<std::string> shippedBoardNames()
{
    std::vector<std::string> names;
    std::error_code ec;
    for (const auto& entry : std::filesystem::directory_iterator(boardDirectory(), ec))
        if (entry.path().extension() == ".toml")
            names.push_back(entry.path().stem().string());
    std::sort(names.begin(), names.end());
    return names;
}

std::filesystem::path resolveBoardProfile(std::string_view nameOrPath, const std::filesystem::path& baseDir)
{
    const std::filesystem::path value(nameOrPath);
    if (nameOrPath.find('/') == std::string_view::npos && value.extension() != ".toml")
        return boardDirectory() / (std::string(nameOrPath) + ".toml");
    return (value.is_relative() ? baseDir / value : value).lexically_normal();
}

void applyBoardCameraDefaults(const BoardProfile& board, CameraConfig& camera)
{
    camera.source = board.camera.source;
    camera.device = board.camera.device;
    camera.format = board.camera.formats.empty() ? "auto" : board.camera.formats.front();
    camera.width = board.camera.width;
    camera.height = board.camera.height;
    camera.fps = board.camera.fps;
}

} // namespace lumar
