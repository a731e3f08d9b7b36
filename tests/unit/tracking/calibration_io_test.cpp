#include <algorithm>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include <gtest/gtest.h>
#include <unistd.h>

#include "core/error.h"
#include "tracking/calibration_io.h"

namespace lumar {
namespace {

namespace fs = std::filesystem;

// A fresh directory per test (ctest runs tests as parallel processes), removed afterwards.
class CalibrationFiles : public testing::Test {
protected:
    void SetUp() override
    {
        const auto* info = testing::UnitTest::GetInstance()->current_test_info();
        dir_ = fs::path(testing::TempDir()) /
               ("lumar_calibration_" + std::string(info->name()) + "_" + std::to_string(::getpid()));
        fs::remove_all(dir_);
        fs::create_directories(dir_);
    }
    void TearDown() override { fs::remove_all(dir_); }

    fs::path write(const std::string& name, const std::string& text) const
    {
        const fs::path file = dir_ / name;
        std::ofstream(file) << text;
        return file;
    }

    // Expects loadCalibration(file) to throw an InputError that starts with the file's name
    // ("FILE: ..." or "FILE:LINE: ..."), is one line and mentions `detail`.
    static void expectInputError(const fs::path& file, const std::string& detail)
    {
        try {
            (void)loadCalibration(file);
            ADD_FAILURE() << "no error for " << file;
        } catch (const InputError& e) {
            const std::string message = e.what();
            EXPECT_EQ(message.rfind(file.string() + ":", 0), 0u) << message;
            EXPECT_EQ(message.find('\n'), std::string::npos) << message;
            EXPECT_NE(message.find(detail), std::string::npos) << message;
        }
    }

    fs::path dir_;
};

std::string calibrationText(const std::string& cameraMatrix, const std::string& distortion,
                            const std::string& size = "image_width: 640\nimage_height: 480\n")
{
    return "%YAML:1.0\n---\n" + size + "camera_matrix: !!opencv-matrix\n   rows: 3\n   cols: 3\n   dt: d\n   data: [ " +
           cameraMatrix + " ]\ndistortion_coefficients: !!opencv-matrix\n   rows: 1\n   cols: " +
           std::to_string(std::count(distortion.begin(), distortion.end(), ',') + 1) + "\n   dt: d\n   data: [ " +
           distortion + " ]\n";
}

const std::string kGoodMatrix = "500., 0., 320., 0., 510., 240., 0., 0., 1.";

TEST(Calibration, LoadsOpenCvsSampleCalibration)
{
    // OpenCV's calibrate sample writes the same keys (plus others, ignored); distortion is 5x1.
    const CameraIntrinsics k =
        loadCalibration(std::string(LUMAR_TEST_DATA_DIR) + "/calib/chessboard/left_intrinsics.yml");
    EXPECT_EQ(k.width, 640);
    EXPECT_EQ(k.height, 480);
    EXPECT_DOUBLE_EQ(k.fx, 5.3591573396163199e+02);
    EXPECT_DOUBLE_EQ(k.fy, 5.3591573396163199e+02);
    EXPECT_DOUBLE_EQ(k.cx, 3.4228315473308373e+02);
    EXPECT_DOUBLE_EQ(k.cy, 2.3557082909788173e+02);
    const std::array<double, 5> distortion{-2.6637260909660682e-01, -3.8588898922304653e-02, 1.7831947042852964e-03,
                                           -2.8122100441115472e-04, 2.3839153080878486e-01};
    for (size_t i = 0; i < 5; ++i)
        EXPECT_DOUBLE_EQ(k.distortion[i], distortion[i]) << i;
}

TEST(Calibration, ShippedFakeCameraCalibrationIsTheDefaultIntrinsics)
{
    const CameraIntrinsics k =
        loadCalibration(std::string(LUMAR_SOURCE_DIR) + "/daemon/assets/calibration/fake_camera_1280x720.yaml");
    const CameraIntrinsics expected = defaultIntrinsics(1280, 720);
    EXPECT_EQ(k.width, expected.width);
    EXPECT_EQ(k.height, expected.height);
    EXPECT_NEAR(k.fx, expected.fx, 1e-9);
    EXPECT_NEAR(k.fy, expected.fy, 1e-9);
    EXPECT_NEAR(k.cx, expected.cx, 1e-9);
    EXPECT_NEAR(k.cy, expected.cy, 1e-9);
    for (double d : k.distortion)
        EXPECT_EQ(d, 0.0);
}

TEST_F(CalibrationFiles, SaveThenLoadGivesTheSameIntrinsics)
{
    CameraIntrinsics k;
    k.width = 1920;
    k.height = 1080;
    k.fx = 1403.123456789012;
    k.fy = 1399.987654321098;
    k.cx = 961.4142135623731;
    k.cy = 538.2718281828459;
    k.distortion = {-0.123456789, 0.0456789012, 1.23e-4, -5.67e-5, -0.0101010101};
    const fs::path file = dir_ / "camera.yaml";
    saveCalibration(file, k);
    const CameraIntrinsics loaded = loadCalibration(file);
    EXPECT_EQ(loaded.width, k.width);
    EXPECT_EQ(loaded.height, k.height);
    // Written with 17 significant digits: exact.
    EXPECT_EQ(loaded.fx, k.fx);
    EXPECT_EQ(loaded.fy, k.fy);
    EXPECT_EQ(loaded.cx, k.cx);
    EXPECT_EQ(loaded.cy, k.cy);
    EXPECT_EQ(loaded.distortion, k.distortion);

    std::ifstream in(file);
    std::ostringstream text;
    text << in.rdbuf();
    EXPECT_NE(text.str().find("calibration_time: "), std::string::npos);
}

TEST_F(CalibrationFiles, ShortAndLongDistortionVectors)
{
    CameraIntrinsics k = loadCalibration(write("four.yaml", calibrationText(kGoodMatrix, "0.1, -0.2, 0.01, 0.02")));
    EXPECT_EQ(k.distortion, (std::array<double, 5>{0.1, -0.2, 0.01, 0.02, 0.0}));
    EXPECT_EQ(k.fx, 500.0);
    EXPECT_EQ(k.fy, 510.0);
    k = loadCalibration(write("eight.yaml", calibrationText(kGoodMatrix, "0.1, -0.2, 0.01, 0.02, 0.3, 0., 0., 0.")));
    EXPECT_EQ(k.distortion, (std::array<double, 5>{0.1, -0.2, 0.01, 0.02, 0.3}));
    expectInputError(write("rational.yaml", calibrationText(kGoodMatrix, "0.1, -0.2, 0.01, 0.02, 0.3, 0.5, 0., 0.")),
                     "coefficient 5 is not zero");
    expectInputError(write("three.yaml", calibrationText(kGoodMatrix, "0.1, -0.2, 0.01")), "distortion_coefficients");
}

TEST_F(CalibrationFiles, MalformedYamlIsAnInputError)
{
    const fs::path broken =
        write("broken.yaml", "%YAML:1.0\n---\ncamera_matrix: !!opencv-matrix\n  rows: [3\n cols: }\n");
    expectInputError(broken, broken.string() + ":5: malformed file");
    expectInputError(write("binary.yaml", std::string("garbage \x01\x02 {{{", 14)), "cannot parse");
    expectInputError(write("empty.yaml", ""), "empty file");
    // OpenCV throws std::length_error here, not cv::Exception (found by mutating files).
    std::string noType = calibrationText(kGoodMatrix, "0, 0, 0, 0, 0");
    noType.replace(noType.rfind("dt: d"), 5, ":dt: d");
    expectInputError(write("no_type.yaml", noType), "cannot parse");
    const std::string shortData =
        "%YAML:1.0\n---\nimage_width: 640\nimage_height: 480\n"
        "camera_matrix: !!opencv-matrix\n   rows: 3\n   cols: 3\n   dt: d\n   data: [ 1, 2 ]\n";
    expectInputError(write("short_data.yaml", shortData), "camera_matrix: not a valid !!opencv-matrix");
}

TEST_F(CalibrationFiles, MissingKeysAreInputErrors)
{
    expectInputError(write("no_matrix.yaml", "%YAML:1.0\n---\nimage_width: 640\nimage_height: 480\n"),
                     "missing key 'camera_matrix'");
    expectInputError(write("no_width.yaml", calibrationText(kGoodMatrix, "0, 0, 0, 0, 0", "image_height: 480\n")),
                     "missing key 'image_width'");
    const std::string noDistortion = "%YAML:1.0\n---\nimage_width: 640\nimage_height: 480\n"
                                     "camera_matrix: !!opencv-matrix\n   rows: 3\n   cols: 3\n   dt: d\n"
                                     "   data: [ " +
                                     kGoodMatrix + " ]\n";
    expectInputError(write("no_distortion.yaml", noDistortion), "missing key 'distortion_coefficients'");
}

TEST_F(CalibrationFiles, ImplausibleValuesAreInputErrors)
{
    const std::string zeros = "0, 0, 0, 0, 0";
    expectInputError(write("negative_fx.yaml", calibrationText("-500., 0., 320., 0., 510., 240., 0., 0., 1.", zeros)),
                     "fx and fy must be positive");
    expectInputError(write("cx_outside.yaml", calibrationText("500., 0., 640., 0., 510., 240., 0., 0., 1.", zeros)),
                     "principal point");
    expectInputError(write("skew.yaml", calibrationText("500., 2., 320., 0., 510., 240., 0., 0., 1.", zeros)),
                     "[fx 0 cx; 0 fy cy; 0 0 1]");
    expectInputError(write("nan.yaml", calibrationText("500., 0., .NaN, 0., 510., 240., 0., 0., 1.", zeros)), "finite");
    expectInputError(write("wide.yaml", calibrationText(kGoodMatrix, zeros, "image_width: 20000\nimage_height: 480\n")),
                     "image_width");
    expectInputError(
        write("real_width.yaml", calibrationText(kGoodMatrix, zeros, "image_width: 640.5\nimage_height: 480\n")),
        "image_width: expected an integer");
    const std::string notMatrix = "%YAML:1.0\n---\nimage_width: 640\nimage_height: 480\ncamera_matrix: 5\n";
    expectInputError(write("scalar_matrix.yaml", notMatrix), "camera_matrix");
    const std::string fourByThree = "%YAML:1.0\n---\nimage_width: 640\nimage_height: 480\n"
                                    "camera_matrix: !!opencv-matrix\n   rows: 4\n   cols: 3\n   dt: d\n"
                                    "   data: [ 1., 0., 0., 0., 1., 0., 0., 0., 1., 0., 0., 0. ]\n";
    expectInputError(write("four_by_three.yaml", fourByThree), "expected 3x3");
}

TEST_F(CalibrationFiles, MissingFileAndDirectoryAreInputErrors)
{
    expectInputError(dir_ / "absent.yaml", "no such file");
    expectInputError(dir_, "not a regular file");
}

TEST_F(CalibrationFiles, UnwritablePathIsARuntimeError)
{
    EXPECT_THROW(saveCalibration(dir_ / "no_such_dir" / "camera.yaml", defaultIntrinsics(640, 480)), RuntimeError);
}

} // namespace
} // namespace lumar
