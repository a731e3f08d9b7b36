// The MJPEG decoder of the V4L2 backend against the virtual camera's own JPEG frames (the
// colour-bar pattern compressed by libturbojpeg at quality 95, 4:2:2, as tests/vcam serves
// them) and against damaged data: truncated, garbled, the wrong size.
#include <cmath>
#include <cstdlib>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <turbojpeg.h>

#include "capture/v4l2/mjpeg_decoder.h"
#include "vcam/vcam_jpeg.h"
#include "vcam/vcam_pattern.h"

namespace lumar {
namespace {

constexpr int kWidth = 640;
constexpr int kHeight = 480;

// Full-range BT.601 luma of an sRGB colour, as JFIF defines Y.
double jfifLuma(const vcam::Rgb& c)
{
    return 0.299 * c.r + 0.587 * c.g + 0.114 * c.b;
}

TEST(MjpegDecoder, ColourBarsAtQuality95DecodeWithinTwoCodeValues)
{
    vcam::MjpegFrames frames;
    const std::vector<uint8_t>& jpeg = frames.frame(0, kWidth, kHeight, 95);
    ASSERT_FALSE(jpeg.empty());
    MjpegDecoder decoder;
    Image8 rgb;
    Image8 luma;
    std::string error;
    ASSERT_TRUE(decoder.decode(jpeg.data(), jpeg.size(), kWidth, kHeight, rgb, luma, error)) << error;
    ASSERT_EQ(rgb.width, kWidth);
    ASSERT_EQ(rgb.height, kHeight);
    ASSERT_EQ(rgb.channels, 3);
    ASSERT_EQ(luma.channels, 1);

    // Inside each bar (8 px clear of its edges, where 4:2:2 chroma and the DCT ring), over
    // every row of the bar band: the decoded colour and luma against the source.
    const auto& bars = vcam::colourBars();
    const int barWidth = kWidth / 8;
    int worstColour = 0;
    double worstLuma = 0.0;
    for (int bar = 0; bar < 8; ++bar) {
        for (int y = 8; y < vcam::blockBandTop(kHeight) - 8; y += 3) {
            for (int x = bar * barWidth + 8; x < (bar + 1) * barWidth - 8; ++x) {
                const uint8_t* p = rgb.at(x, y);
                const vcam::Rgb& c = bars[size_t(bar)];
                worstColour = std::max({worstColour, std::abs(p[0] - c.r), std::abs(p[1] - c.g), std::abs(p[2] - c.b)});
                worstLuma = std::max(worstLuma, std::abs(*luma.at(x, y) - jfifLuma(c)));
            }
        }
    }
    EXPECT_LE(worstColour, 2);
    EXPECT_LE(worstLuma, 1.5);

    // The whole picture, edges included: PSNR against the source RGB.
    std::vector<uint8_t> source(size_t(kWidth) * kHeight * 3);
    vcam::drawPatternRgb(kWidth, kHeight, 0, source.data());
    double squared = 0.0;
    for (size_t i = 0; i < source.size(); ++i) {
        const double d = double(rgb.data[i]) - double(source[i]);
        squared += d * d;
    }
    const double psnr = 10.0 * std::log10(255.0 * 255.0 / (squared / double(source.size())));
    EXPECT_GT(psnr, 35.0);
    RecordProperty("worst_colour_error", worstColour);
    RecordProperty("psnr_db", std::to_string(psnr));
}

TEST(MjpegDecoder, MovingBlockLandsInTheLumaPlane)
{
    vcam::MjpegFrames frames;
    MjpegDecoder decoder;
    Image8 rgb;
    Image8 luma;
    std::string error;
    for (int64_t frame : {0, 7, 31}) {
        const std::vector<uint8_t>& jpeg = frames.frame(frame, kWidth, kHeight, 95);
        ASSERT_TRUE(decoder.decode(jpeg.data(), jpeg.size(), kWidth, kHeight, rgb, luma, error)) << error;
        const int left = vcam::blockLeft(frame, kWidth);
        const int row = (vcam::blockBandTop(kHeight) + kHeight) / 2;
        EXPECT_GT(*luma.at(left + vcam::kBlockWidth / 2, row), 250) << "frame " << frame;
        if (left >= 8) {
            EXPECT_LT(*luma.at(left - 8, row), 5) << "frame " << frame;
        }
        EXPECT_LT(*luma.at((left + vcam::kBlockWidth + 8) % kWidth, row), 5) << "frame " << frame;
    }
}

TEST(MjpegDecoder, GreyJpegFillsAllThreeChannels)
{
    std::vector<uint8_t> grey(size_t(kWidth) * kHeight);
    for (size_t i = 0; i < grey.size(); ++i) {
        grey[i] = uint8_t((i % kWidth) * 255 / (kWidth - 1));
    }
    tjhandle compressor = tjInitCompress();
    ASSERT_NE(compressor, nullptr);
    unsigned char* jpeg = nullptr;
    unsigned long size = 0;
    ASSERT_EQ(
        tjCompress2(compressor, grey.data(), kWidth, kWidth, kHeight, TJPF_GRAY, &jpeg, &size, TJSAMP_GRAY, 95, 0), 0);
    MjpegDecoder decoder;
    Image8 rgb;
    Image8 luma;
    std::string error;
    const bool decoded = decoder.decode(jpeg, size, kWidth, kHeight, rgb, luma, error);
    tjFree(jpeg);
    tjDestroy(compressor);
    ASSERT_TRUE(decoded) << error;
    int worst = 0;
    for (size_t i = 0; i < grey.size(); ++i) {
        worst = std::max(worst, std::abs(int(luma.data[i]) - int(grey[i])));
        ASSERT_EQ(rgb.data[3 * i], luma.data[i]);
        ASSERT_EQ(rgb.data[3 * i + 2], luma.data[i]);
    }
    EXPECT_LE(worst, 3);
}

TEST(MjpegDecoder, DamagedFramesAreRejectedNotThrown)
{
    vcam::MjpegFrames frames;
    const std::vector<uint8_t> jpeg = frames.frame(3, kWidth, kHeight, 95);
    MjpegDecoder decoder;
    Image8 rgb;
    Image8 luma;
    std::string error;

    // The vcam's "corrupt frame" fault: cut after a third, garbage after.
    std::vector<uint8_t> corrupt(jpeg.size());
    corrupt.resize(vcam::corruptJpeg(jpeg, corrupt.data(), corrupt.size()));
    EXPECT_FALSE(decoder.decode(corrupt.data(), corrupt.size(), kWidth, kHeight, rgb, luma, error));
    EXPECT_FALSE(error.empty());

    // Truncated (a short USB transfer): the end of the scan missing.
    error.clear();
    EXPECT_FALSE(decoder.decode(jpeg.data(), jpeg.size() * 2 / 3, kWidth, kHeight, rgb, luma, error));
    EXPECT_FALSE(error.empty());

    // Not a JPEG at all, and nothing.
    std::vector<uint8_t> noise(4096);
    std::srand(7);
    for (uint8_t& b : noise) {
        b = uint8_t(std::rand());
    }
    EXPECT_FALSE(decoder.decode(noise.data(), noise.size(), kWidth, kHeight, rgb, luma, error));
    EXPECT_FALSE(decoder.decode(jpeg.data(), 0, kWidth, kHeight, rgb, luma, error));

    // A whole JPEG of another size than negotiated.
    error.clear();
    EXPECT_FALSE(decoder.decode(jpeg.data(), jpeg.size(), 1280, 720, rgb, luma, error));
    EXPECT_EQ(error, "decodes to 640x480, negotiated 1280x720");

    // The decoder is still good for the next frame.
    EXPECT_TRUE(decoder.decode(jpeg.data(), jpeg.size(), kWidth, kHeight, rgb, luma, error)) << error;
}

} // namespace
} // namespace lumar
