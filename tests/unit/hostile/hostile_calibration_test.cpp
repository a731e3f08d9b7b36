// Calibration files that crashed or stalled OpenCV's FileStorage (issue 16) and their
// neighbours: lumar now reads the YAML itself (tracking/calibration_yaml.h), so each of these
// must be a one-line InputError, quickly.
#include <filesystem>
#include <string>

#include <gtest/gtest.h>

#include "hostile_support.h"
#include "tracking/calibration_io.h"
#include "tracking/calibration_yaml.h"
#include "unit/render/render_test_support.h"

namespace lumar::test {
namespace {

const std::string kGood = "%YAML:1.0\n---\nimage_width: 640\nimage_height: 480\n"
                          "camera_matrix: !!opencv-matrix\n   rows: 3\n   cols: 3\n   dt: d\n"
                          "   data: [ 500., 0., 320., 0.,\n       510., 240., 0., 0., 1. ]\n"
                          "distortion_coefficients: !!opencv-matrix\n   rows: 1\n   cols: 5\n   dt: d\n"
                          "   data: [ 0., 0., 0., 0., 0. ]\n";

std::string expectCalibrationRejected(const ScratchDir& dir, const std::string& name, const std::string& text,
                                      const std::string& detail)
{
    const std::filesystem::path file = dir.file(name);
    writeText(file, text);
    return expectRejected([&] { (void)loadCalibration(file); }, file.string() + ":", detail);
}

TEST(HostileCalibration, TheGoodFileStillLoads)
{
    const ScratchDir dir;
    writeText(dir.file("good.yaml"), kGood);
    const CameraIntrinsics k = loadCalibration(dir.file("good.yaml"));
    EXPECT_EQ(k.width, 640);
    EXPECT_EQ(k.fy, 510.0);
    EXPECT_EQ(k.cy, 240.0);
}

TEST(HostileCalibration, XmlAndJsonAreRefusedWithoutOpenCv)
{
    const ScratchDir dir;
    expectCalibrationRejected(dir, "prolog.xml", std::string("<?xml version=\"1.0\"?\0\0\0>\n<opencv_storage>", 40),
                              "cannot parse a control character");
    expectCalibrationRejected(dir, "xml.yaml", "<?xml version=\"1.0\"?>\n<opencv_storage>\n%YAML:1.0\n",
                              "not XML or JSON");
    expectCalibrationRejected(dir, "yaml_in_xml.yaml", "<?xml version=\"1.0\"?>\n%YAML:1.0\n---\na: 1\n",
                              "not XML or JSON");
    expectCalibrationRejected(dir, "json.yaml", "{ \"image_width\": 640 }\n", "not XML or JSON");
}

TEST(HostileCalibration, DeepNestingIsRefusedAtTheFirstLevel)
{
    const ScratchDir dir;
    expectCalibrationRejected(dir, "brackets.yaml", "%YAML:1.0\nimage_width: " + repeat("[", 100000) + "\n",
                              "unexpected '['");
    expectCalibrationRejected(dir, "braces.yaml", "%YAML:1.0\nimage_width: " + repeat("{", 100000) + "\n",
                              "unsupported YAML");
    // Indentation nests blocks in YAML: an unknown key's block is skipped, not descended into.
    std::string indented = kGood + "extra:\n";
    for (int i = 1; i < 1000; ++i)
        indented += std::string(size_t(i), ' ') + "k" + std::to_string(i) + ":\n";
    writeText(dir.file("indented.yaml"), indented);
    EXPECT_EQ(loadCalibration(dir.file("indented.yaml")).width, 640);
}

TEST(HostileCalibration, OverlongAndOutOfRangeNumbersAreRefused)
{
    const ScratchDir dir;
    std::string longNumber = kGood;
    longNumber.replace(longNumber.find("500."), 4, "5" + std::string(100000, '0') + ".");
    expectCalibrationRejected(dir, "long.yaml", longNumber, "is not a number");
    expectCalibrationRejected(dir, "wide.yaml", "image_width: 99999999999999999999\n", "image_width");
    std::string bigRows = kGood;
    bigRows.replace(bigRows.find("rows: 3"), 7, "rows: 2147483647");
    expectCalibrationRejected(dir, "rows.yaml", bigRows, "not a valid !!opencv-matrix");
    std::string manyChannels = kGood;
    manyChannels.replace(manyChannels.find("dt: d"), 5, "dt: \"3000000000d\"");
    expectCalibrationRejected(dir, "channels.yaml", manyChannels, "dt must be one of");
}

TEST(HostileCalibration, StructuralDamageIsRefusedWithItsLine)
{
    const ScratchDir dir;
    expectCalibrationRejected(dir, "unclosed.yaml", "image_width: [ 1, 2\n", ":1: malformed file");
    expectCalibrationRejected(dir, "dup.yaml", kGood + "image_width: 640\n", "duplicate key");
    expectCalibrationRejected(dir, "two_docs.yaml", kGood + "---\n" + kGood, "more than one YAML document");
    expectCalibrationRejected(dir, "anchor.yaml", "image_width: &a 640\n", "unsupported YAML");
    expectCalibrationRejected(dir, "indent.yaml", "  image_width: 640\n", "unexpected indentation");
    expectCalibrationRejected(dir, "nul.yaml",
                              std::string("image_width: 6\0"
                                          "40\n",
                                          16),
                              "control character");
    const std::filesystem::path big = dir.file("big.yaml");
    writeText(big, kGood + "# " + std::string(2 << 20, 'x') + "\n");
    expectRejected([&] { (void)loadCalibration(big); }, big.string() + ": ", "larger than 1 MiB");
}

TEST(HostileCalibration, YamlNumberSpellings)
{
    EXPECT_EQ(calibration_yaml::toNumber("1."), 1.0);
    EXPECT_EQ(calibration_yaml::toNumber("-.5"), -0.5);
    EXPECT_EQ(calibration_yaml::toNumber("+2e3"), 2000.0);
    EXPECT_TRUE(std::isinf(*calibration_yaml::toNumber("-.Inf")));
    EXPECT_TRUE(std::isnan(*calibration_yaml::toNumber(".NaN")));
    EXPECT_FALSE(calibration_yaml::toNumber("inf"));
    EXPECT_FALSE(calibration_yaml::toNumber("1e999"));
    EXPECT_FALSE(calibration_yaml::toNumber("0x10"));
    EXPECT_FALSE(calibration_yaml::toNumber(""));
}

} // namespace
} // namespace lumar::test
