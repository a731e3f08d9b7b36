#include "tracking/chessboard_calibration.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <limits>
#include <system_error>

#include <opencv2/calib3d.hpp>
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

#include "core/error.h"
#include "core/log.h"
#include "output/frame_writer.h"

namespace lumar {
namespace {

namespace fs = std::filesystem;

// OpenCV's corner finder needs more than two inner corners per side; the upper bound only
// keeps absurd input from allocating absurd corner lists.
constexpr int kMinBoardSide = 3;
constexpr int kMaxBoardSide = 100;
// cornerSubPix's half window: OpenCV's calibration sample uses 11 px. A window that reaches
// the neighbouring corners sees their edges too and pulls the estimate, so on small boards it
// shrinks to half the corner spacing (measured on OpenCV's left02.jpg, corners 21 px apart:
// its reprojection RMS drops from 1.22 to 0.89 px).
constexpr int kMaxSubPixelHalfWindow = 11;
constexpr int kMinSubPixelHalfWindow = 2;

std::string describeBoard(ChessboardSize board)
{
    return std::to_string(board.columns) + "x" + std::to_string(board.rows);
}

// Names the set of images in whole-set errors: their folder when they share one.
std::string describeImageSet(const std::vector<fs::path>& images)
{
    if (images.empty())
        return "no images";
    const fs::path folder = images.front().parent_path();
    for (const fs::path& image : images)
        if (image.parent_path() != folder)
            return std::to_string(images.size()) + " images";
    return folder.empty() ? std::string(".") : folder.string();
}

bool isCalibrationImageName(const fs::path& file)
{
    std::string extension = file.extension().string();
    std::transform(extension.begin(), extension.end(), extension.begin(),
                   [](unsigned char c) { return char(std::tolower(c)); });
    return extension == ".jpg" || extension == ".jpeg" || extension == ".png";
}

// Decoded with stb_image (readImage), as every other image lumar reads, not OpenCV's
// imgcodecs, which the binary would link only for this. The grey differs from what
// imread(IMREAD_GRAYSCALE) gave by at most 1 level: a grey JPEG's samples by IDCT rounding
// (0.46..0.55 % of the pixels of each of OpenCV's 13 sample boards), a colour image's also by
// the formula, stb's (77 R + 150 G + 29 B) >> 8 against OpenCV's 0.299 R + 0.587 G + 0.114 B
// rounded (13.5 % of random RGB pixels, none by more than 1). On the 13 boards the refined
// corners move by at most 0.015 px (mean 0.0007 px) and fx, fy, cx, cy by under 0.003 px.
// stb also rejects a truncated JPEG, which imread decoded with its missing part grey.
Image8 readGray(const fs::path& file)
{
    const std::string name = file.string();
    std::error_code ec;
    if (!fs::is_regular_file(file, ec))
        throw InputError(name + ": cannot read: " + (fs::exists(file, ec) ? "not a regular file" : "no such file"));
    return readImage(file, 1); // InputError "FILE: cannot read the image: REASON"
}

int subPixelHalfWindow(const std::vector<cv::Point2f>& corners, ChessboardSize board)
{
    double spacing = std::numeric_limits<double>::max();
    for (int r = 0; r < board.rows; ++r)
        for (int c = 0; c < board.columns; ++c) {
            const cv::Point2f& p = corners[size_t(r * board.columns + c)];
            if (c + 1 < board.columns)
                spacing = std::min(spacing, cv::norm(corners[size_t(r * board.columns + c + 1)] - p));
            if (r + 1 < board.rows)
                spacing = std::min(spacing, cv::norm(corners[size_t((r + 1) * board.columns + c)] - p));
        }
    return std::clamp(int(spacing / 2.0), kMinSubPixelHalfWindow, kMaxSubPixelHalfWindow);
}

// The board's corners in its own plane (z = 0), in findChessboardCorners' order: row by
// row, columns fastest.
std::vector<cv::Point3f> boardCorners(ChessboardSize board, double squareSize)
{
    std::vector<cv::Point3f> points;
    points.reserve(size_t(board.columns) * size_t(board.rows));
    for (int r = 0; r < board.rows; ++r)
        for (int c = 0; c < board.columns; ++c)
            points.emplace_back(float(c * squareSize), float(r * squareSize), 0.0f);
    return points;
}

double reprojectionRms(const std::vector<cv::Point3f>& object, const std::vector<cv::Point2f>& detected,
                       const cv::Mat& cameraMatrix, const cv::Mat& distortion, const cv::Mat& rvec, const cv::Mat& tvec)
{
    std::vector<cv::Point2f> projected;
    cv::projectPoints(object, rvec, tvec, cameraMatrix, distortion, projected);
    double sumSquares = 0.0;
    for (size_t i = 0; i < detected.size(); ++i) {
        const cv::Point2f d = projected[i] - detected[i];
        sumSquares += double(d.x) * d.x + double(d.y) * d.y;
    }
    return std::sqrt(sumSquares / double(detected.size()));
}

CameraIntrinsics toIntrinsics(const cv::Mat& cameraMatrix, const cv::Mat& distortion, cv::Size imageSize)
{
    CameraIntrinsics k;
    k.width = imageSize.width;
    k.height = imageSize.height;
    k.fx = cameraMatrix.at<double>(0, 0);
    k.fy = cameraMatrix.at<double>(1, 1);
    k.cx = cameraMatrix.at<double>(0, 2);
    k.cy = cameraMatrix.at<double>(1, 2);
    const cv::Mat flat = distortion.reshape(1, 1);
    for (int i = 0; i < int(k.distortion.size()) && i < int(flat.total()); ++i)
        k.distortion[size_t(i)] = flat.at<double>(0, i);
    return k;
}

// calibrateCamera returns garbage rather than failing when the views are degenerate (all
// fronto-parallel, say); catch what would make a calibration file unusable.
bool plausible(const CameraIntrinsics& k)
{
    for (double d : k.distortion)
        if (!std::isfinite(d))
            return false;
    return std::isfinite(k.fx) && std::isfinite(k.fy) && k.fx > 0.0 && k.fy > 0.0 && k.cx >= 0.0 && k.cx < k.width &&
           k.cy >= 0.0 && k.cy < k.height;
}

} // namespace

std::vector<fs::path> chessboardImagesIn(const fs::path& dir)
{
    std::error_code ec;
    if (!fs::is_directory(dir, ec))
        throw InputError(dir.string() + ": not a directory");
    std::vector<fs::path> images;
    fs::directory_iterator it(dir, ec);
    if (ec)
        throw InputError(dir.string() + ": cannot list: " + ec.message());
    for (const fs::directory_entry& entry : it)
        if (isCalibrationImageName(entry.path()) && !entry.is_directory(ec))
            images.push_back(entry.path());
    if (images.empty())
        throw InputError(dir.string() + ": no .jpg, .jpeg or .png images");
    std::sort(images.begin(), images.end());
    return images;
}

ChessboardCalibration calibrateFromChessboards(const std::vector<fs::path>& images, ChessboardSize board,
                                               double squareSize)
{
    const std::string setName = describeImageSet(images);
    if (board.columns < kMinBoardSide || board.rows < kMinBoardSide || board.columns > kMaxBoardSide ||
        board.rows > kMaxBoardSide)
        throw InputError(setName + ": a " + describeBoard(board) + " board is unusable: each side needs " +
                         std::to_string(kMinBoardSide) + ".." + std::to_string(kMaxBoardSide) + " inner corners");
    if (!std::isfinite(squareSize) || squareSize <= 0.0)
        throw InputError(setName + ": the square size must be a positive number");

    const cv::Size pattern(board.columns, board.rows);
    const std::vector<cv::Point3f> object = boardCorners(board, squareSize);
    // The adaptive threshold and normalisation find boards under uneven light; the fast
    // check rejects an image without a board in milliseconds instead of a long search.
    const int findFlags = cv::CALIB_CB_ADAPTIVE_THRESH | cv::CALIB_CB_NORMALIZE_IMAGE | cv::CALIB_CB_FAST_CHECK;
    const cv::TermCriteria subPixelStop(cv::TermCriteria::EPS + cv::TermCriteria::COUNT, 30, 1e-4);

    ChessboardCalibration result;
    std::vector<std::string> usedFiles;
    std::vector<std::vector<cv::Point2f>> imageCorners;
    cv::Size imageSize;
    for (const fs::path& file : images) {
        const Image8 image = readGray(file);
        // A view of the pixels, which OpenCV only reads.
        const cv::Mat gray(image.height, image.width, CV_8UC1, const_cast<uint8_t*>(image.data.data()));
        if (imageSize.empty())
            imageSize = gray.size();
        else if (gray.size() != imageSize)
            throw InputError(file.string() + ": image is " + std::to_string(gray.cols) + "x" +
                             std::to_string(gray.rows) + " but " + images.front().string() + " is " +
                             std::to_string(imageSize.width) + "x" + std::to_string(imageSize.height));
        std::vector<cv::Point2f> corners;
        if (!cv::findChessboardCorners(gray, pattern, corners, findFlags) || corners.size() != object.size()) {
            LUMAR_LOG(Tracking, Info) << file.string() << ": the " << describeBoard(board) << " board was not found";
            result.rejected.push_back(file.string());
            continue;
        }
        const int halfWindow = subPixelHalfWindow(corners, board);
        cv::cornerSubPix(gray, corners, cv::Size(halfWindow, halfWindow), cv::Size(-1, -1), subPixelStop);
        LUMAR_LOG(Tracking, Debug) << file.string() << ": board found, sub-pixel half window " << halfWindow;
        usedFiles.push_back(file.string());
        imageCorners.push_back(std::move(corners));
    }
    if (imageCorners.size() < size_t(kMinCalibrationImages))
        throw InputError(setName + ": the " + describeBoard(board) + " board was found in only " +
                         std::to_string(imageCorners.size()) + " images (need " +
                         std::to_string(kMinCalibrationImages) + ")");

    const std::vector<std::vector<cv::Point3f>> objectPoints(imageCorners.size(), object);
    cv::Mat cameraMatrix;
    cv::Mat distortion;
    std::vector<cv::Mat> rvecs;
    std::vector<cv::Mat> tvecs;
    try {
        result.rmsPx =
            cv::calibrateCamera(objectPoints, imageCorners, imageSize, cameraMatrix, distortion, rvecs, tvecs);
    } catch (const cv::Exception& e) {
        throw InputError(setName + ": calibration failed: " + e.err);
    }
    result.intrinsics = toIntrinsics(cameraMatrix, distortion, imageSize);
    if (!plausible(result.intrinsics) || !std::isfinite(result.rmsPx))
        throw InputError(setName + ": calibration failed: implausible result (use views of the board tilted in "
                                   "different directions)");
    for (size_t i = 0; i < imageCorners.size(); ++i)
        result.perImage.push_back(
            {usedFiles[i], reprojectionRms(object, imageCorners[i], cameraMatrix, distortion, rvecs[i], tvecs[i])});
    LUMAR_LOG(Tracking, Info) << "calibrated from " << imageCorners.size() << " images of " << setName << ": RMS "
                              << result.rmsPx << " px";
    return result;
}

} // namespace lumar
