#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <unistd.h>

#include "core/error.h"
#include "tracking/calibration_io.h"
#include "tracking/chessboard_calibration.h"

namespace lumar {
namespace {

namespace fs = std::filesystem;

// OpenCV's 13 sample views of a board with 9x6 inner corners, 640x480 (tests/data/calib/SOURCES.md).
const fs::path kSampleDir = fs::path(LUMAR_TEST_DATA_DIR) / "calib/chessboard";
constexpr ChessboardSize kSampleBoard{9, 6};
constexpr double kSquareMetres = 0.025;

std::vector<fs::path> sampleImages()
{
    std::vector<fs::path> images;
    for (const fs::path& file : chessboardImagesIn(kSampleDir))
        if (file.filename().string().rfind("left", 0) == 0)
            images.push_back(file);
    return images;
}

// The 13 images are calibrated once for the whole suite: it is the slow part.
class SampleCalibration : public testing::Test {
protected:
    static void SetUpTestSuite()
    {
        const auto start = std::chrono::steady_clock::now();
        calibration_ = new ChessboardCalibration(calibrateFromChessboards(sampleImages(), kSampleBoard, kSquareMetres));
        const std::chrono::duration<double> took = std::chrono::steady_clock::now() - start;
        std::printf("calibrated 13 images in %.3f s: fx %.3f fy %.3f cx %.3f cy %.3f RMS %.4f px\n", took.count(),
                    calibration_->intrinsics.fx, calibration_->intrinsics.fy, calibration_->intrinsics.cx,
                    calibration_->intrinsics.cy, calibration_->rmsPx);
        const auto& d = calibration_->intrinsics.distortion;
        std::printf("  distortion %.4f %.4f %.5f %.5f %.4f\n", d[0], d[1], d[2], d[3], d[4]);
        for (const ImageReprojectionError& e : calibration_->perImage)
            std::printf("  %s %.3f px\n", fs::path(e.file).filename().c_str(), e.rmsPx);
    }
    static void TearDownTestSuite()
    {
        delete calibration_;
        calibration_ = nullptr;
    }
    static const ChessboardCalibration& calibration() { return *calibration_; }

private:
    static inline ChessboardCalibration* calibration_ = nullptr;
};

TEST_F(SampleCalibration, AgreesWithOpenCvsOwnCalibration)
{
    // OpenCV's calibration sample on the same images (fixed aspect ratio, so fx = fy there).
    const CameraIntrinsics reference = loadCalibration(kSampleDir / "left_intrinsics.yml");
    const ChessboardCalibration& c = calibration();
    ASSERT_TRUE(c.rejected.empty());
    ASSERT_EQ(c.perImage.size(), 13u);
    EXPECT_EQ(c.intrinsics.width, 640);
    EXPECT_EQ(c.intrinsics.height, 480);
    // Measured here: fx 534.69 and fy 534.71 (-0.23 % against 535.92), cx 341.84 and cy 235.16
    // (0.44 and 0.41 px off); our fit frees the aspect ratio and shrinks the sub-pixel window on
    // left02.jpg. 1 % and 5 px leave room for another OpenCV version's corner finder while
    // still catching a wrong board model or a lost distortion term (several % and tens of px).
    EXPECT_NEAR(c.intrinsics.fx, reference.fx, 0.01 * reference.fx);
    EXPECT_NEAR(c.intrinsics.fy, reference.fy, 0.01 * reference.fy);
    EXPECT_NEAR(c.intrinsics.cx, reference.cx, 5.0);
    EXPECT_NEAR(c.intrinsics.cy, reference.cy, 5.0);
    // The lens's strong barrel distortion is found: k1 measured -0.273 against the reference's
    // -0.266 (k2 and k3 trade off against each other, so they are not compared).
    EXPECT_NEAR(c.intrinsics.distortion[0], reference.distortion[0], 0.02);
    // OpenCV's sample reports 0.393 px on these images; we measure 0.336 px (0.409 px with the
    // sample's fixed 11 px sub-pixel window). 0.5 px is above both, below a poor fit's ~1 px.
    EXPECT_LT(c.rmsPx, 0.5);
}

TEST_F(SampleCalibration, PerImageErrorsAgreeWithTheOverallRmsAndOpenCv)
{
    const ChessboardCalibration& c = calibration();
    ASSERT_EQ(c.perImage.size(), 13u);
    // Every image has the same 54 corners, so the overall RMS is the RMS of the per-image
    // ones: this checks the per-image reprojection against calibrateCamera's own figure.
    double sumSquares = 0.0;
    for (const ImageReprojectionError& e : c.perImage)
        sumSquares += e.rmsPx * e.rmsPx;
    EXPECT_NEAR(std::sqrt(sumSquares / double(c.perImage.size())), c.rmsPx, 1e-6);

    cv::FileStorage reference((kSampleDir / "left_intrinsics.yml").string(), cv::FileStorage::READ);
    cv::Mat perView;
    reference["per_view_reprojection_errors"] >> perView;
    ASSERT_EQ(perView.total(), 13u);
    const std::vector<fs::path> images = sampleImages();
    for (size_t i = 0; i < c.perImage.size(); ++i) {
        EXPECT_EQ(c.perImage[i].file, images[i].string());
        // OpenCV's per-view figures run 0.16 to 1.18 px; ours are within 0.09 px of them, but
        // for left02.jpg, where the corners are 21 px apart and the narrower sub-pixel window
        // brings 1.18 down to 0.89 px.
        const float opencv = perView.at<float>(int(i));
        if (images[i].filename() == "left02.jpg")
            EXPECT_LT(c.perImage[i].rmsPx, opencv - 0.2);
        else
            EXPECT_NEAR(c.perImage[i].rmsPx, opencv, 0.12) << c.perImage[i].file;
    }
}

// A fresh directory per test (ctest runs tests as parallel processes), removed afterwards.
class CalibrationFolder : public testing::Test {
protected:
    void SetUp() override
    {
        const auto* info = testing::UnitTest::GetInstance()->current_test_info();
        dir_ = fs::path(testing::TempDir()) /
               ("lumar_chessboard_" + std::string(info->name()) + "_" + std::to_string(::getpid()));
        fs::remove_all(dir_);
        fs::create_directories(dir_);
    }
    void TearDown() override { fs::remove_all(dir_); }

    // Copies the first `count` sample images into the folder.
    void copySamples(size_t count) const
    {
        const std::vector<fs::path> images = sampleImages();
        for (size_t i = 0; i < count && i < images.size(); ++i)
            fs::copy_file(images[i], dir_ / images[i].filename());
    }

    fs::path dir_;
};

void expectInputError(const fs::path& dir, const std::string& prefix, const std::string& detail)
{
    try {
        (void)calibrateFromChessboards(chessboardImagesIn(dir), kSampleBoard, kSquareMetres);
        ADD_FAILURE() << "no error for " << dir;
    } catch (const InputError& e) {
        const std::string message = e.what();
        EXPECT_EQ(message.rfind(prefix + ":", 0), 0u) << message;
        EXPECT_EQ(message.find('\n'), std::string::npos) << message;
        EXPECT_NE(message.find(detail), std::string::npos) << message;
    }
}

TEST_F(CalibrationFolder, SavedCalibrationLoadsBackEqual)
{
    copySamples(13);
    const ChessboardCalibration c = calibrateFromChessboards(chessboardImagesIn(dir_), kSampleBoard, kSquareMetres);
    const fs::path file = dir_ / "camera.yaml";
    saveCalibration(file, c.intrinsics, c.rmsPx);
    const CameraIntrinsics loaded = loadCalibration(file);
    EXPECT_EQ(loaded.width, c.intrinsics.width);
    EXPECT_EQ(loaded.height, c.intrinsics.height);
    // FileStorage writes doubles with 17 significant digits: the round trip is exact.
    EXPECT_EQ(loaded.fx, c.intrinsics.fx);
    EXPECT_EQ(loaded.fy, c.intrinsics.fy);
    EXPECT_EQ(loaded.cx, c.intrinsics.cx);
    EXPECT_EQ(loaded.cy, c.intrinsics.cy);
    EXPECT_EQ(loaded.distortion, c.intrinsics.distortion);
    cv::FileStorage yaml(file.string(), cv::FileStorage::READ);
    EXPECT_EQ(double(yaml["avg_reprojection_error"]), c.rmsPx);
}

TEST_F(CalibrationFolder, ImageWithoutTheBoardIsRejectedNotFatal)
{
    copySamples(4);
    // A plain grey frame and one with only a few squares: neither holds the whole board.
    cv::imwrite((dir_ / "blank.png").string(), cv::Mat(480, 640, CV_8UC1, cv::Scalar(128)));
    cv::Mat partial(480, 640, CV_8UC1, cv::Scalar(255));
    for (int i = 0; i < 3; ++i)
        cv::rectangle(partial, cv::Rect(100 + 80 * i, 100 + 40 * (i % 2), 40, 40), cv::Scalar(0), cv::FILLED);
    cv::imwrite((dir_ / "partial.png").string(), partial);
    const auto start = std::chrono::steady_clock::now();
    const ChessboardCalibration c = calibrateFromChessboards(chessboardImagesIn(dir_), kSampleBoard, kSquareMetres);
    const std::chrono::duration<double> took = std::chrono::steady_clock::now() - start;
    std::printf("4 boards + 2 misses calibrated in %.3f s\n", took.count());
    EXPECT_EQ(c.rejected, (std::vector<std::string>{(dir_ / "blank.png").string(), (dir_ / "partial.png").string()}));
    ASSERT_EQ(c.perImage.size(), 4u);
    EXPECT_EQ(c.perImage[0].file, (dir_ / "left01.jpg").string());
}

TEST_F(CalibrationFolder, TwoBoardsAreNotEnough)
{
    copySamples(2);
    cv::imwrite((dir_ / "blank.png").string(), cv::Mat(480, 640, CV_8UC1, cv::Scalar(128)));
    expectInputError(dir_, dir_.string(), "the 9x6 board was found in only 2 images (need 3)");
}

TEST_F(CalibrationFolder, NonImageNamedJpgIsNamed)
{
    copySamples(3);
    std::ofstream(dir_ / "x.jpg") << "not a JPEG\n";
    expectInputError(dir_, (dir_ / "x.jpg").string(), "cannot read the image");
}

TEST_F(CalibrationFolder, TruncatedImageIsNamed)
{
    copySamples(3);
    // The first 5000 of left04.jpg's 25150 bytes: a valid header, then the data stops.
    std::ifstream in(sampleImages()[3], std::ios::binary);
    std::string bytes(5000, '\0');
    ASSERT_TRUE(in.read(bytes.data(), std::streamsize(bytes.size())));
    std::ofstream(dir_ / "left04.jpg", std::ios::binary) << bytes;
    expectInputError(dir_, (dir_ / "left04.jpg").string(), "cannot read the image");
}

TEST_F(CalibrationFolder, ImageOfAnotherSizeIsNamed)
{
    copySamples(3);
    cv::Mat half;
    cv::resize(cv::imread(sampleImages()[3].string()), half, cv::Size(320, 240), 0, 0, cv::INTER_AREA);
    cv::imwrite((dir_ / "left99.png").string(), half);
    expectInputError(dir_, (dir_ / "left99.png").string(), "image is 320x240 but");
}

TEST_F(CalibrationFolder, BoardNeedsThreeInnerCornersPerSide)
{
    copySamples(3);
    EXPECT_THROW((void)calibrateFromChessboards(chessboardImagesIn(dir_), ChessboardSize{2, 6}, kSquareMetres),
                 InputError);
    EXPECT_THROW((void)calibrateFromChessboards(chessboardImagesIn(dir_), kSampleBoard, 0.0), InputError);
}

TEST_F(CalibrationFolder, ListsImagesByNameAndIgnoresOtherFiles)
{
    for (const char* name : {"b.PNG", "a.jpg", "c.jpeg", "notes.txt", "d.yaml"})
        std::ofstream(dir_ / name) << "x";
    fs::create_directories(dir_ / "e.jpg");
    EXPECT_EQ(chessboardImagesIn(dir_), (std::vector<fs::path>{dir_ / "a.jpg", dir_ / "b.PNG", dir_ / "c.jpeg"}));
}

TEST_F(CalibrationFolder, FolderWithoutImagesIsAnError)
{
    std::ofstream(dir_ / "notes.txt") << "x";
    EXPECT_THROW((void)chessboardImagesIn(dir_), InputError);
    EXPECT_THROW((void)chessboardImagesIn(dir_ / "missing"), InputError);
}

} // namespace
} // namespace lumar
