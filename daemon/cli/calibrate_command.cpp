// lumar calibrate: camera intrinsics from a folder of chessboard photos, written as OpenCV
// FileStorage YAML for --calib. Prints each image's reprojection error so that a bad view
// (motion blur, a misdetected board) stands out and can be removed.
#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include "commands.h"
#include "core/error.h"
#include "tracking/calibration_io.h"
#include "tracking/chessboard_calibration.h"

namespace lumar {
namespace {

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

int calibrateCommand(const CalibrateCommandOptions& options)
{
    configureLogLevel(options.logLevel);
    const std::vector<std::filesystem::path> images = chessboardImagesIn(options.images);
    const ChessboardCalibration calibration =
        calibrateFromChessboards(images, {options.boardColumns, options.boardRows}, options.square);
    saveCalibration(options.out, calibration.intrinsics, calibration.rmsPx);
    printReport(images, calibration);
    std::printf("wrote %s\n", options.out.c_str());
    return kExitOk;
}

} // namespace lumar
