// Camera calibration from photos of a flat chessboard (DESIGN.md §5), with OpenCV's
// corner finder and calibrateCamera: pinhole intrinsics plus five distortion terms.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "core/camera_model.h"

namespace lumar {

// The board's inner corners (where four squares meet), not its squares: a board of
// 10x7 squares has 9x6 inner corners.
struct ChessboardSize {
    int columns = 0;
    int rows = 0;
};

struct ImageReprojectionError {
    std::string file;
    double rmsPx = 0.0; // root mean square distance of its detected to reprojected corners
};

struct ChessboardCalibration {
    CameraIntrinsics intrinsics;
    double rmsPx = 0.0;                           // over every corner of every used image
    std::vector<ImageReprojectionError> perImage; // the images used, in input order
    std::vector<std::string> rejected;            // the images where the board was not found
};

inline constexpr int kMinCalibrationImages = 3;

// The *.jpg, *.jpeg and *.png files (any letter case) directly in `dir`, sorted by name.
// Throws InputError "DIR: ..." when `dir` is not a readable directory or holds no such file.
std::vector<std::filesystem::path> chessboardImagesIn(const std::filesystem::path& dir);

// Calibrates from `images`, all of one size. `squareSize` (the side of one square, in any
// unit) scales only the board poses, never the intrinsics. Images where the whole board is
// not found are listed in `rejected`. Throws InputError naming the file for an unreadable
// image or one whose size differs from the first, and "DIR: ..." (the images' folder) when
// the board is found in fewer than kMinCalibrationImages or the solution is implausible.
ChessboardCalibration calibrateFromChessboards(const std::vector<std::filesystem::path>& images, ChessboardSize board,
                                               double squareSize);

} // namespace lumar
