// Y4M: what lumar writes it reads back, known YCbCr values decode to the right colours in
// both ranges, and every malformed file is an InputError naming the file.
#include <cmath>
#include <fstream>
#include <sstream>
#include <string>

#include <gtest/gtest.h>

#include "capture/y4m_source.h"
#include "core/error.h"
#include "output/frame_writer.h"
#include "output/y4m_writer.h"
#include "temp_dir.h"

namespace lumar {
namespace {

using test::TempDir;
using test::writeFile;

CameraConfig y4mConfig(const std::filesystem::path& file, bool loop = false)
{
    CameraConfig config;
    config.source = "y4m";
    config.path = file;
    config.loop = loop;
    return config;
}

std::string readAll(const std::filesystem::path& file)
{
    std::ifstream in(file, std::ios::binary);
    std::ostringstream out;
    out << in.rdbuf();
    return out.str();
}

// A smooth colour image: every channel changes by at most 3 code values per pixel.
Image8 gradient(int width, int height, int shift)
{
    Image8 image(width, height, 3);
    for (int y = 0; y < height; ++y) {
        for (int x = 0; x < width; ++x) {
            uint8_t* p = image.at(x, y);
            p[0] = uint8_t(20 + 3 * x + shift);
            p[1] = uint8_t(30 + 2 * y + x);
            p[2] = uint8_t(220 - 2 * x - y);
        }
    }
    return image;
}

void expectInputErrorNaming(const std::filesystem::path& file, const std::string& fragment, bool duringNext = false)
{
    try {
        Y4mSource source(y4mConfig(file));
        if (duringNext) {
            Frame frame;
            while (source.next(frame)) {
            }
        }
        ADD_FAILURE() << "no error for " << fragment;
    } catch (const InputError& e) {
        const std::string message = e.what();
        EXPECT_NE(message.find(file.string()), std::string::npos) << message;
        EXPECT_NE(message.find(fragment), std::string::npos) << message;
        EXPECT_EQ(message.find('\n'), std::string::npos) << message;
    }
}

TEST(Y4mWriter, FrameRateIsARational)
{
    EXPECT_EQ(y4mFrameRate(30.0), "30:1");
    EXPECT_EQ(y4mFrameRate(60.0), "60:1");
    EXPECT_EQ(y4mFrameRate(30000.0 / 1001.0), "30000:1001");
    EXPECT_EQ(y4mFrameRate(24000.0 / 1001.0), "24000:1001");
    EXPECT_EQ(y4mFrameRate(12.5), "25:2");
    EXPECT_THROW(y4mFrameRate(0.0), InputError);
}

TEST(Y4mWriter, WritesTheDocumentedHeader)
{
    TempDir dir;
    const auto file = dir / "out.y4m";
    {
        const auto writer = openFrameWriter(file, 30.0);
        writer->write(gradient(8, 4, 0));
        writer->finish();
    }
    const std::string bytes = readAll(file);
    const std::string header = "YUV4MPEG2 W8 H4 F30:1 Ip A1:1 C420jpeg XCOLORRANGE=FULL\n";
    ASSERT_GE(bytes.size(), header.size());
    EXPECT_EQ(bytes.substr(0, header.size()), header);
    EXPECT_EQ(bytes.size(), header.size() + 6 + 8 * 4 * 3 / 2);
}

TEST(Y4mWriter, RejectsOddSizesAndSizeChanges)
{
    TempDir dir;
    const auto writer = openFrameWriter(dir / "odd.y4m", 30.0);
    EXPECT_THROW(writer->write(gradient(7, 4, 0)), InputError);
    writer->write(gradient(8, 4, 0));
    EXPECT_THROW(writer->write(gradient(8, 6, 0)), InputError);
}

TEST(Y4m, WriterToReaderRoundTripIsWithinThreeCodeValues)
{
    TempDir dir;
    const auto file = dir / "round.y4m";
    {
        const auto writer = openFrameWriter(file, 25.0);
        for (int f = 0; f < 3; ++f) {
            writer->write(gradient(64, 48, 5 * f));
        }
        writer->finish();
    }
    Y4mSource source(y4mConfig(file));
    EXPECT_EQ(source.width(), 64);
    EXPECT_EQ(source.height(), 48);
    EXPECT_DOUBLE_EQ(source.fps(), 25.0);
    EXPECT_TRUE(source.fullRange());
    Frame frame;
    int worst = 0;
    for (int f = 0; f < 3; ++f) {
        ASSERT_TRUE(source.next(frame));
        EXPECT_EQ(frame.sequence, uint64_t(f));
        EXPECT_EQ(frame.timestampNs, int64_t(f) * 40'000'000);
        const Image8 expected = gradient(64, 48, 5 * f);
        for (size_t i = 0; i < expected.data.size(); ++i) {
            worst = std::max(worst, std::abs(int(frame.rgb.data[i]) - int(expected.data[i])));
        }
        // Luma comes from the Y plane: BT.601 of the original colour, within rounding.
        for (int y = 0; y < 48; ++y) {
            for (int x = 0; x < 64; ++x) {
                const uint8_t* p = expected.at(x, y);
                const double luma = 0.299 * p[0] + 0.587 * p[1] + 0.114 * p[2];
                EXPECT_LE(std::abs(*frame.luma.at(x, y) - luma), 1.0);
            }
        }
    }
    EXPECT_LE(worst, 3);
    EXPECT_FALSE(source.next(frame));
}

// Two 2×2 4:4:4 frames: pixel by pixel (Y, Cb, Cr) chosen so the BT.601 colours are known.
std::string yuv444File(const std::string& range, const std::vector<std::array<uint8_t, 3>>& pixels)
{
    std::string data = "YUV4MPEG2 W2 H2 F30:1 C444" + range + "\nFRAME\n";
    for (int plane = 0; plane < 3; ++plane) {
        for (const auto& p : pixels) {
            data.push_back(char(p[size_t(plane)]));
        }
    }
    return data;
}

void expectPixel(const Frame& frame, int index, int r, int g, int b, int tolerance)
{
    const uint8_t* p = frame.rgb.data.data() + 3 * index;
    EXPECT_NEAR(p[0], r, tolerance) << "pixel " << index;
    EXPECT_NEAR(p[1], g, tolerance) << "pixel " << index;
    EXPECT_NEAR(p[2], b, tolerance) << "pixel " << index;
}

TEST(Y4mSource, DecodesLimitedRangeByDefault)
{
    TempDir dir;
    const auto file = dir / "limited.y4m";
    // Black, white, red and blue in limited-range BT.601 (ITU-R BT.601 tables).
    writeFile(file, yuv444File("", {{16, 128, 128}, {235, 128, 128}, {81, 90, 240}, {41, 240, 110}}));
    Y4mSource source(y4mConfig(file));
    EXPECT_FALSE(source.fullRange());
    Frame frame;
    ASSERT_TRUE(source.next(frame));
    expectPixel(frame, 0, 0, 0, 0, 0);
    expectPixel(frame, 1, 255, 255, 255, 0);
    expectPixel(frame, 2, 255, 0, 0, 2);
    expectPixel(frame, 3, 0, 0, 255, 2);
    EXPECT_EQ(frame.luma.data[0], 0);
    EXPECT_EQ(frame.luma.data[1], 255);
}

TEST(Y4mSource, DecodesFullRangeWhenTheHeaderSaysSo)
{
    TempDir dir;
    const auto file = dir / "full.y4m";
    // Full range: Y = 0.299 R + 0.587 G + 0.114 B, Cb = 128 + (B − Y) / 1.772,
    // Cr = 128 + (R − Y) / 1.402. Red: (76, 85, 255); grey 128: (128, 128, 128).
    writeFile(file, yuv444File(" XCOLORRANGE=FULL", {{0, 128, 128}, {255, 128, 128}, {76, 85, 255}, {128, 128, 128}}));
    Y4mSource source(y4mConfig(file));
    EXPECT_TRUE(source.fullRange());
    Frame frame;
    ASSERT_TRUE(source.next(frame));
    expectPixel(frame, 0, 0, 0, 0, 0);
    expectPixel(frame, 1, 255, 255, 255, 0);
    expectPixel(frame, 2, 255, 0, 0, 2);
    expectPixel(frame, 3, 128, 128, 128, 0);
}

TEST(Y4mSource, DecodesMonochrome)
{
    TempDir dir;
    const auto file = dir / "mono.y4m";
    writeFile(file, std::string("YUV4MPEG2 W2 H1 F10:1 Cmono XCOLORRANGE=FULL\nFRAME\n") + char(10) + char(200));
    Y4mSource source(y4mConfig(file));
    EXPECT_DOUBLE_EQ(source.fps(), 10.0);
    Frame frame;
    ASSERT_TRUE(source.next(frame));
    expectPixel(frame, 0, 10, 10, 10, 0);
    expectPixel(frame, 1, 200, 200, 200, 0);
}

TEST(Y4mSource, LoopsWithIncreasingSequence)
{
    TempDir dir;
    const auto file = dir / "loop.y4m";
    {
        const auto writer = openFrameWriter(file, 30.0);
        writer->write(gradient(4, 2, 0));
        writer->write(gradient(4, 2, 100));
        writer->finish();
    }
    Y4mSource source(y4mConfig(file, /*loop=*/true));
    Frame frame;
    std::vector<uint8_t> firstRed;
    for (int k = 0; k < 5; ++k) {
        ASSERT_TRUE(source.next(frame));
        EXPECT_EQ(frame.sequence, uint64_t(k));
        firstRed.push_back(frame.rgb.data[0]);
    }
    EXPECT_EQ(firstRed[0], firstRed[2]);
    EXPECT_EQ(firstRed[0], firstRed[4]);
    EXPECT_EQ(firstRed[1], firstRed[3]);
    EXPECT_NE(firstRed[0], firstRed[1]);
}

TEST(Y4mSource, UsesConfiguredFpsWhenTheHeaderHasNone)
{
    TempDir dir;
    const auto file = dir / "nofps.y4m";
    writeFile(file, std::string("YUV4MPEG2 W2 H1 Cmono\nFRAME\n") + "ab");
    CameraConfig config = y4mConfig(file);
    config.fps = 12.0;
    Y4mSource source(config);
    EXPECT_DOUBLE_EQ(source.fps(), 12.0);
}

TEST(Y4mSource, MalformedFilesAreInputErrorsNamingTheFile)
{
    TempDir dir;
    const std::string frame420(2 * 2 * 3 / 2, '\x80');
    const auto write = [&](const std::string& name, const std::string& bytes) {
        const auto file = dir / name;
        writeFile(file, bytes);
        return file;
    };
    expectInputErrorNaming(dir / "missing.y4m", "cannot open");
    expectInputErrorNaming(write("magic.y4m", "RIFF0000WAVE\n" + frame420), "not a YUV4MPEG2");
    expectInputErrorNaming(write("binary.y4m", std::string(10000, 'x')), "not a YUV4MPEG2");
    expectInputErrorNaming(write("nowidth.y4m", "YUV4MPEG2 H2 F30:1\nFRAME\n" + frame420), "no W");
    expectInputErrorNaming(write("badwidth.y4m", "YUV4MPEG2 Wx H2\nFRAME\n" + frame420), "bad width");
    expectInputErrorNaming(write("zero.y4m", "YUV4MPEG2 W0 H2\nFRAME\n" + frame420), "outside 1..16384");
    expectInputErrorNaming(write("huge.y4m", "YUV4MPEG2 W20000 H2\nFRAME\n" + frame420), "outside 1..16384");
    expectInputErrorNaming(write("odd.y4m", "YUV4MPEG2 W3 H2\nFRAME\n" + frame420), "even width");
    expectInputErrorNaming(write("deep.y4m", "YUV4MPEG2 W2 H2 C420p10\nFRAME\n" + frame420),
                           "unsupported colour space");
    expectInputErrorNaming(write("rate.y4m", "YUV4MPEG2 W2 H2 F30:0\nFRAME\n" + frame420), "bad frame rate");
    expectInputErrorNaming(write("empty.y4m", "YUV4MPEG2 W2 H2\n"), "no frames");
    expectInputErrorNaming(write("short.y4m", "YUV4MPEG2 W2 H2\nFRAME\n" + frame420.substr(3)), "truncated");
    // The header promises a huge frame the file does not hold: refused before allocating.
    expectInputErrorNaming(write("big.y4m", "YUV4MPEG2 W16384 H16384\nFRAME\n" + frame420), "truncated");
    expectInputErrorNaming(write("marker.y4m", "YUV4MPEG2 W2 H2\nFRAME\n" + frame420 + "FRAMX\n" + frame420),
                           "missing FRAME marker", true);
    expectInputErrorNaming(write("tail.y4m", "YUV4MPEG2 W2 H2\nFRAME\n" + frame420 + "FRAME\n" + frame420.substr(2)),
                           "truncated", true);
}

} // namespace
} // namespace lumar
