// `lumar render` from the virtual camera with camera.convert = "gpu" (the renderer converts
// the NV12/YUYV planes, read in place from the driver's lent buffers) and "cpu" (the capture
// thread converts): the same picture within one code value, for both layouts and both
// matrices and ranges the driver can report.
#include <cstdlib>
#include <string>

#include <gtest/gtest.h>

#include "output/frame_writer.h"
#include "run_lumar.h"
#include "vcam/vcam_pattern.h"

namespace lumar {
namespace {

constexpr int kWidth = 640;
constexpr int kHeight = 480;
constexpr int kFrames = 3;

struct Variant {
    const char* format;       // camera.format
    const char* encoding;     // LUMAR_VCAM_YCBCR_ENC
    const char* quantization; // LUMAR_VCAM_QUANTIZATION
};

// Renders kFrames frames with `convert` into `dir`; returns lumar's stderr.
std::string render(const Variant& v, const std::string& convert, const std::filesystem::path& dir)
{
    const std::filesystem::path config = dir / "scene.toml";
    {
        std::ofstream out(config);
        out << "[camera]\nsource = \"v4l2\"\ndevice = \"/dev/video-lumar-test\"\nwidth = " << kWidth
            << "\nheight = " << kHeight << "\nfps = 30\nformat = \"" << v.format << "\"\nconvert = \"" << convert
            << "\"\n";
    }
    const test::ProcessResult r = test::runLumar(
        {"render", "--config", config.string(), "--frames", std::to_string(kFrames), "--out",
         (dir / "frame_%03d.png").string()},
        dir,
        {std::string("LUMAR_VCAM_YCBCR_ENC=") + v.encoding, std::string("LUMAR_VCAM_QUANTIZATION=") + v.quantization});
    EXPECT_EQ(r.exitCode, 0) << r.err;
    return r.err;
}

class VcamConvert : public ::testing::TestWithParam<Variant> {
protected:
    void SetUp() override
    {
        const char* preload = std::getenv("LD_PRELOAD");
        if (preload == nullptr || std::string(preload).find("lumar_vcam") == std::string::npos)
            GTEST_SKIP() << "run through ctest, which preloads liblumar_vcam.so";
    }
};

TEST_P(VcamConvert, GpuConversionMatchesCpuConversion)
{
    const Variant v = GetParam();
    const std::string name = std::string("vcam_convert_") + v.format + v.encoding + v.quantization;
    const auto gpuDir = test::scratchDirectory(name + "_gpu");
    const auto cpuDir = test::scratchDirectory(name + "_cpu");
    const std::string gpuLog = render(v, "gpu", gpuDir);
    EXPECT_NE(gpuLog.find("converted on the GPU"), std::string::npos);
    // zero_copy = "auto" (the default): the frames borrow the driver's buffers, which the
    // renderer uploads in place here (llvmpipe cannot import dmabufs).
    EXPECT_NE(gpuLog.find("buffers lent to the renderer (zero-copy), exported as dmabufs"), std::string::npos)
        << gpuLog;
    EXPECT_EQ(render(v, "cpu", cpuDir).find("converted on the GPU"), std::string::npos);

    // The bars above the moving block are the same in every frame, so a frame the camera
    // dropped in one run and not the other cannot make the comparison flaky.
    const int barsBottom = vcam::blockBandTop(kHeight);
    for (int k = 0; k < kFrames; ++k) {
        char file[32];
        std::snprintf(file, sizeof file, "frame_%03d.png", k);
        const Image8 gpu = readImage(gpuDir / file, 3);
        const Image8 cpu = readImage(cpuDir / file, 3);
        ASSERT_EQ(gpu.width, kWidth);
        ASSERT_EQ(gpu.height, kHeight);
        ASSERT_EQ(cpu.width, kWidth);
        ASSERT_EQ(cpu.height, kHeight);
        int worst = 0;
        for (int y = 0; y < barsBottom; ++y)
            for (int x = 0; x < kWidth * 3; ++x)
                worst = std::max(worst, std::abs(int(gpu.row(y)[x]) - int(cpu.row(y)[x])));
        EXPECT_LE(worst, 1) << file;
        // Not two blank pictures: the first bar is 75 % white, the seventh 75 % blue.
        for (int c = 0; c < 3; ++c)
            EXPECT_NEAR(gpu.at(kWidth / 16, barsBottom / 2)[c], 191, 2) << file << " channel " << c;
        EXPECT_NEAR(gpu.at(kWidth * 13 / 16, barsBottom / 2)[2], 191, 2) << file;
        EXPECT_NEAR(gpu.at(kWidth * 13 / 16, barsBottom / 2)[0], 0, 2) << file;
    }
}

INSTANTIATE_TEST_SUITE_P(Formats, VcamConvert,
                         ::testing::Values(Variant{"nv12", "601", "limited"}, Variant{"nv12", "709", "full"},
                                           Variant{"yuyv", "709", "limited"}, Variant{"yuyv", "601", "full"}));

} // namespace
} // namespace lumar
