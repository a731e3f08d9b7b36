// Board profiles (board/*.toml, DESIGN.md §3): what differs between the boards lumar runs on —
// camera stack and formats, display driver, connector and plane, GL quirks — kept as data so
// the code has no per-board #ifdefs. The schema is documented in board/README.md. Parsing
// validates like the configuration does and throws InputError "FILE:LINE: key: what".
#pragma once

#include <filesystem>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace lumar {

struct CameraConfig;

struct BoardCameraProfile {
    std::string source = "v4l2";        // "v4l2" | "libcamera"
    std::string device = "/dev/video0"; // v4l2: the device node; libcamera: a camera id or "auto"
    std::vector<std::string> formats;   // preference order, [camera] format names; empty: the source's own order
    int width = 1280;
    int height = 720;
    double fps = 30.0;
};

struct BoardDisplayProfile {
    std::vector<std::string> drmDrivers; // drmGetVersion names in preference order; empty: any
    std::string connector = "auto";      // a DRM connector name ("HDMI-A-1") or "auto" (the first connected)
    std::string plane = "primary";       // "primary" | "overlay"
    bool modifiers = true;               // false: add framebuffers without format modifiers (linear)
};

struct BoardProfile {
    std::filesystem::path sourceFile;
    std::string name;
    std::string description;
    BoardCameraProfile camera;
    BoardDisplayProfile display;
    std::vector<std::string> glQuirks; // each one of knownGlQuirks()

    [[nodiscard]] bool hasQuirk(std::string_view quirk) const;
};

// The GL quirks a board file may name (board/README.md says what each one changes).
std::span<const std::string_view> knownGlQuirks();

// Parses and validates profile text; `fileName` is used in messages. Throws InputError.
BoardProfile parseBoardProfile(std::string_view text, const std::filesystem::path& fileName);

// Reads and parses a board file. Throws InputError (including "cannot read").
BoardProfile loadBoardProfile(const std::filesystem::path& file);

// True when `file` is TOML with a top-level [board] table: a board profile rather than a
// configuration (which names its board with a `board = "..."` string). False for unreadable
// or malformed files, so the configuration parser reports their errors.
bool isBoardProfileFile(const std::filesystem::path& file);

// Where the shipped profiles live: the asset directory's board/ when installed
// (share/lumar/board), else the source tree's board/.
std::filesystem::path boardDirectory();

// The names of the profiles in boardDirectory() (file names without ".toml"), sorted.
std::vector<std::string> shippedBoardNames();

// The file a configuration's `board = "..."` names: a bare name ("x86-uvc") is a file in
// boardDirectory(); a value with a '/' or ending in ".toml" is a path, relative ones against
// `baseDir`. Does not check that the file exists.
std::filesystem::path resolveBoardProfile(std::string_view nameOrPath, const std::filesystem::path& baseDir);

// The profile's camera values as the starting point that a configuration's [camera] table
// then overrides: source, device, size, rate, and its most preferred format.
void applyBoardCameraDefaults(const BoardProfile& board, CameraConfig& camera);

} // namespace lumar
