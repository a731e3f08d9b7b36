// Radiance .hdr loading: the real map against MANIFEST §3, small hand-encoded files whose
// pixels are known exactly, and corrupt files (including the ones that make Debian's
// stb_image read past the end or loop forever) rejected with a one-line InputError.
#include <cmath>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "gles_renderer/assets/environment_map.h"
#include "render_test_support.h"

namespace lumar {
namespace {

using test::expectInputErrorNamingFile;
using test::ScratchDir;

const std::filesystem::path kVenice = test::sourcePath("daemon/assets/env/venice_sunset_1k.hdr");

std::string expectRejected(const std::filesystem::path& file)
{
    return expectInputErrorNamingFile([&] { (void)loadHdrImage(file); }, file);
}

std::vector<uint8_t> header(int width, int height)
{
    const std::string text = "#?RADIANCE\n# written by a lumar test\nFORMAT=32-bit_rle_rgbe\n\n-Y " +
                             std::to_string(height) + " +X " + std::to_string(width) + "\n";
    return {text.begin(), text.end()};
}

// An RLE scanline of width 8 whose four component planes are each one run of `rgbe[k]`.
void appendRunScanline(std::vector<uint8_t>& bytes, const uint8_t rgbe[4])
{
    bytes.insert(bytes.end(), {2, 2, 0, 8});
    for (int k = 0; k < 4; ++k) {
        bytes.insert(bytes.end(), {uint8_t(128 + 8), rgbe[k]});
    }
}

TEST(HdrImage, VeniceSunsetMatchesTheManifest)
{
    const ImageF image = loadHdrImage(kVenice);
    ASSERT_EQ(image.width, 1024);
    ASSERT_EQ(image.height, 512);
    ASSERT_EQ(image.channels, 3);
    int bestRow = -1, bestCol = -1;
    double best = -1.0;
    for (int r = 0; r < image.height; ++r) {
        for (int c = 0; c < image.width; ++c) {
            const float* p = image.at(c, r);
            for (int k = 0; k < 3; ++k) {
                ASSERT_TRUE(std::isfinite(p[k]) && p[k] >= 0.0f) << "row " << r << " col " << c;
            }
            const double luminance = 0.2126 * p[0] + 0.7152 * p[1] + 0.0722 * p[2];
            if (luminance > best) {
                best = luminance;
                bestRow = r;
                bestCol = c;
            }
        }
    }
    // MANIFEST §3 / sh9_reference.json: the sun, luminance ~2090.5 at row 246, column 614
    // (row 0 = the file's first scanline, the top of the sky).
    EXPECT_NEAR(bestRow, 246, 2);
    EXPECT_NEAR(bestCol, 614, 2);
    EXPECT_NEAR(best, 2090.5, 2090.5 * 0.01);
}

TEST(HdrImage, FlatPixelsDecodeExactlyTopRowFirst)
{
    ScratchDir dir;
    std::vector<uint8_t> bytes = header(2, 2); // width < 8: stored flat, no RLE
    // RGBE: value = mantissa * 2^(exponent - 136); exponent 0 means black.
    bytes.insert(bytes.end(), {128, 64, 32, 129, 0, 0, 0, 0, 255, 0, 0, 136, 1, 2, 3, 128});
    const auto file = dir.file("flat.hdr");
    test::writeBytes(file, bytes);
    const ImageF image = loadHdrImage(file);
    ASSERT_EQ(image.width, 2);
    ASSERT_EQ(image.height, 2);
    EXPECT_EQ(image.data,
              (std::vector<float>{1.0f, 0.5f, 0.25f, 0, 0, 0, 255.0f, 0, 0, 1 / 256.0f, 2 / 256.0f, 3 / 256.0f}));
}

TEST(HdrImage, RunLengthEncodedRowsDecodeExactly)
{
    ScratchDir dir;
    std::vector<uint8_t> bytes = header(8, 2);
    const uint8_t top[4] = {128, 128, 128, 130}; // 128 * 2^-6 = 2 in every channel
    const uint8_t bottom[4] = {64, 32, 16, 136}; // (64, 32, 16)
    appendRunScanline(bytes, top);
    appendRunScanline(bytes, bottom);
    const auto file = dir.file("rle.hdr");
    test::writeBytes(file, bytes);
    const ImageF image = loadHdrImage(file);
    ASSERT_EQ(image.width, 8);
    ASSERT_EQ(image.height, 2);
    for (int c = 0; c < 8; ++c) {
        EXPECT_EQ(image.at(c, 0)[0], 2.0f);
        EXPECT_EQ(image.at(c, 1)[0], 64.0f);
        EXPECT_EQ(image.at(c, 1)[1], 32.0f);
        EXPECT_EQ(image.at(c, 1)[2], 16.0f);
    }
}

TEST(HdrImage, MalformedRunLengthStreamsAreRejected)
{
    ScratchDir dir;
    const uint8_t pixel[4] = {128, 128, 128, 130};
    std::vector<uint8_t> oneRow = header(8, 2);
    appendRunScanline(oneRow, pixel);

    // Truncated exactly at a scanline boundary: stb_image would decode zeros and succeed.
    test::writeBytes(dir.file("one-row.hdr"), oneRow);
    EXPECT_NE(expectRejected(dir.file("one-row.hdr")).find("truncated"), std::string::npos);

    // A zero run length: stb_image 2.27 loops forever on it.
    std::vector<uint8_t> zeroRun = oneRow;
    zeroRun.insert(zeroRun.end(), {2, 2, 0, 8, 0});
    test::writeBytes(dir.file("zero-run.hdr"), zeroRun);
    EXPECT_NE(expectRejected(dir.file("zero-run.hdr")).find("bad run length"), std::string::npos);

    // A run longer than the scanline.
    std::vector<uint8_t> longRun = oneRow;
    longRun.insert(longRun.end(), {2, 2, 0, 8, 128 + 9, 1});
    test::writeBytes(dir.file("long-run.hdr"), longRun);
    expectRejected(dir.file("long-run.hdr"));

    // A scanline announcing the wrong width.
    std::vector<uint8_t> wrongWidth = oneRow;
    wrongWidth.insert(wrongWidth.end(), {2, 2, 0, 9});
    test::writeBytes(dir.file("wrong-width.hdr"), wrongWidth);
    expectRejected(dir.file("wrong-width.hdr"));
}

TEST(HdrImage, BadHeadersAreRejected)
{
    ScratchDir dir;
    struct Case {
        const char* name;
        std::string text;
    };
    const Case cases[] = {
        {"no-format", "#?RADIANCE\n\n-Y 1 +X 1\n"},
        {"other-layout", "#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n+Y 1 +X 1\n"},
        {"zero-size", "#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 0 +X 4\n"},
        {"negative-size", "#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y -3 +X 4\n"},
        {"huge-size", "#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 100000 +X 100000\n"},
        {"header-only", "#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n"},
    };
    for (const Case& c : cases) {
        SCOPED_TRACE(c.name);
        const auto file = dir.file(std::string(c.name) + ".hdr");
        test::writeText(file, c.text);
        expectRejected(file);
    }
}

TEST(HdrImage, NonHdrMissingEmptyAndGarbageFilesAreRejected)
{
    ScratchDir dir;
    const auto png = test::testDataPath("apriltag/tag36h11/tag36_11_00000.png");
    EXPECT_NE(expectRejected(png).find("not a Radiance .hdr image"), std::string::npos);
    EXPECT_NE(expectRejected(dir.file("absent.hdr")).find("no such file"), std::string::npos);
    test::writeBytes(dir.file("empty.hdr"), {});
    expectRejected(dir.file("empty.hdr"));
    std::vector<uint8_t> garbage(5000);
    for (size_t i = 0; i < garbage.size(); ++i) {
        garbage[i] = uint8_t(i * 7919u >> 3);
    }
    test::writeBytes(dir.file("garbage.hdr"), garbage);
    expectRejected(dir.file("garbage.hdr"));
}

TEST(HdrImage, TruncatedVeniceSunsetIsRejectedAtAnyLength)
{
    ScratchDir dir;
    const std::vector<uint8_t> whole = test::readBytes(kVenice);
    ASSERT_EQ(whole.size(), 1397783u);
    for (const size_t length : {size_t(5), size_t(30), size_t(70), size_t(200), size_t(100000), whole.size() / 2,
                                whole.size() - 100, whole.size() - 1}) {
        SCOPED_TRACE("first " + std::to_string(length) + " bytes");
        const auto file = dir.file("venice-" + std::to_string(length) + ".hdr");
        test::writeBytes(file, std::vector<uint8_t>(whole.begin(), whole.begin() + std::ptrdiff_t(length)));
        expectRejected(file);
    }
}

} // namespace
} // namespace lumar
