// lumar calibrate: camera intrinsics from a folder of chessboard photos, written as OpenCV
// FileStorage YAML for --calib. Prints each image's reprojection error so that a bad view
// (motion blur, a misdetected board) stands out and can be removed.
#include <algorithm>
#include <charconv>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <map>
#include <string>
#include <vector>

#include "command_line.h"
#include "commands.h"
#include "core/error.h"
#include "core/log.h"
#include "tracking/calibration_io.h"
#include "tracking/chessboard_calibration.h"

namespace lumar {
namespace {

constexpr const char* kHelp = R"(usage: lumar calibrate --images DIR --board COLSxROWS --square S --out FILE
                       [--log-level SPEC]

Calibrates the camera from photos of a flat chessboard: every *.jpg, *.jpeg and *.png in DIR,
all of one size, taken from varied angles (at least 3 must show the whole board). Prints
each image's reprojection RMS (or "board not found"), the overall RMS and the intrinsics,
and writes them as OpenCV FileStorage YAML (camera_matrix, distortion_coefficients,
image_width, image_height), the format --calib reads.
  --images DIR        folder of board photos, used in name order
  --board COLSxROWS   inner corners (where four squares meet), e.g. 9x6 for 10x7 squares
  --square S          side of one square in metres (scales the board poses only)
  --out FILE          calibration file to write
)";

constexpr long kMaxBoardSide = 100;

int parseBoardSide(const std::string& text, const std::string& whole)
{
    int value = 0;
    const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
    if (text.empty() || ec != std::errc() || end != text.data() + text.size())
        throw UsageError("option --board: '" + whole + "' is not COLSxROWS (inner corners, e.g. 9x6)");
    if (value < 3 || value > kMaxBoardSide)
        throw UsageError("option --board: " + whole + ": each side needs 3.." + std::to_string(kMaxBoardSide) +
                         " inner corners");
    return value;
}

ChessboardSize parseBoard(const std::string& text)
{
    const size_t x = text.find_first_of("xX");
    if (x == std::string::npos)
        throw UsageError("option --board: '" + text + "' is not COLSxROWS (inner corners, e.g. 9x6)");
    return {parseBoardSide(text.substr(0, x), text), parseBoardSide(text.substr(x + 1), text)};
}

std::string requiredValue(const CommandLine& cl, const std::string& name, const char* what)
{
    const auto value = cl.value(name);
    if (!value || value->empty())
        throw UsageError("--" + name + " " + what + " is required");
    return *value;
}

void printReport(const std::vector<std::filesystem::path>& images, const ChessboardCalibration& c)
{
    std::map<std::string, double> rmsByFile;
    for (const ImageReprojectionError& e : c.perImage)
        rmsByFile[e.file] = e.rmsPx;
    size_t nameWidth = 5; // "image"
    for (const std::filesystem::path& image : images)
        nameWidth = std::max(nameWidth, image.filename().string().size());
    const int width = int(nameWidth);

    std::printf("%-*s  RMS px\n", width, "image");
    for (const std::filesystem::path& image : images) {
        const std::string name = image.filename().string();
        const auto found = rmsByFile.find(image.string());
        if (found == rmsByFile.end())
            std::printf("%-*s  board not found\n", width, name.c_str());
        else
            std::printf("%-*s  %.3f\n", width, name.c_str(), found->second);
    }
    const CameraIntrinsics& k = c.intrinsics;
    std::printf("overall RMS %.3f px over %zu of %zu images\n", c.rmsPx, c.perImage.size(), images.size());
    std::printf("image %dx%d  fx %.3f  fy %.3f  cx %.3f  cy %.3f\n", k.width, k.height, k.fx, k.fy, k.cx, k.cy);
    std::printf("distortion k1 %.6f  k2 %.6f  p1 %.6f  p2 %.6f  k3 %.6f\n", k.distortion[0], k.distortion[1],
                k.distortion[2], k.distortion[3], k.distortion[4]);
}

} // namespace

int calibrateCommand(const Args& args)
{
    const CommandLine cl(args, {{"images"}, {"board"}, {"square"}, {"out"}, {"log-level"}});
    if (cl.helpRequested()) {
        std::fputs(kHelp, stdout);
        return kExitOk;
    }
    if (!cl.positional().empty())
        throw UsageError("unexpected argument '" + cl.positional().front() + "'");
    const std::string dir = requiredValue(cl, "images", "DIR");
    const ChessboardSize board = parseBoard(requiredValue(cl, "board", "COLSxROWS"));
    (void)requiredValue(cl, "square", "S");
    const double square = cl.number("square", 0.0, std::numeric_limits<double>::min(), 1000.0);
    const std::string out = requiredValue(cl, "out", "FILE");
    if (!log::configure(cl.value("log-level").value_or("warn")))
        throw UsageError("bad --log-level");

    const std::vector<std::filesystem::path> images = chessboardImagesIn(dir);
    const ChessboardCalibration calibration = calibrateFromChessboards(images, board, square);
    saveCalibration(out, calibration.intrinsics, calibration.rmsPx);
    printReport(images, calibration);
    std::printf("wrote %s\n", out.c_str());
    return kExitOk;
}

} // namespace lumar
