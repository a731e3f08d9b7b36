// Radiance .hdr and Y4M headers that asked for too much (issue 16).
#include <filesystem>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "capture/y4m_header.h"
#include "gles_renderer/assets/environment_map.h"
#include "hostile_support.h"
#include "unit/render/render_test_support.h"

namespace lumar::test {
namespace {

// A valid run-length encoded .hdr of one grey value: 4 components per scanline, each as runs
// of up to 127 pixels (2 bytes a run).
std::string runLengthHdr(int width, int height)
{
    std::string text =
        "#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y " + std::to_string(height) + " +X " + std::to_string(width) + "\n";
    std::string row = {2, 2, char(width >> 8), char(width & 0xff)};
    for (int component = 0; component < 4; ++component) {
        for (int left = width; left > 0; left -= 127) {
            const int run = std::min(left, 127);
            row += char(128 + run);
            row += char(component == 3 ? 128 : 100);
        }
    }
    text.reserve(text.size() + row.size() * size_t(height));
    for (int y = 0; y < height; ++y)
        text += row;
    return text;
}

TEST(HostileHdr, HugeHeaderIsRefusedBeforeAllocating)
{
    const ScratchDir dir;
    // The fuzzed file's header, without its 8 MB of runs: refused from the header alone.
    writeText(dir.file("huge.hdr"), "#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 8192 +X 16384\n");
    expectRejected([&] { (void)loadHdrImage(dir.file("huge.hdr")); }, dir.file("huge.hdr").string() + ": ",
                   "16384x8192 is larger than the supported 8192 pixels a side and 4096x2048 pixels in all");
    // Whole, valid files just over each cap.
    writeText(dir.file("wide.hdr"), runLengthHdr(8193, 2));
    expectRejected([&] { (void)loadHdrImage(dir.file("wide.hdr")); }, dir.file("wide.hdr").string() + ": ",
                   "8193x2 is larger");
    writeText(dir.file("many.hdr"), runLengthHdr(4097, 2048));
    expectRejected([&] { (void)loadHdrImage(dir.file("many.hdr")); }, dir.file("many.hdr").string() + ": ",
                   "4097x2048 is larger");
}

TEST(HostileHdr, RunLengthFilesWithinTheCapDecode)
{
    const ScratchDir dir;
    writeText(dir.file("ok.hdr"), runLengthHdr(300, 3));
    const ImageF image = loadHdrImage(dir.file("ok.hdr"));
    EXPECT_EQ(image.width, 300);
    EXPECT_EQ(image.height, 3);
    EXPECT_FLOAT_EQ(image.data[0], 100.0f / 256.0f); // RGBE: mantissa x 2^(exponent - 136)
}

TEST(HostileY4m, FrameRatesOutsideTheRangeAreRefused)
{
    for (const char* rate : {"F1:1000", "F1:2147483647", "F2147483647:1", "F1001:1"})
        expectRejected([&] { (void)parseY4mHeader(std::string("YUV4MPEG2 W16 H16 ") + rate, "evil.y4m"); },
                       "evil.y4m: ", "outside 0.1..1000 frames per second");
    EXPECT_EQ(parseY4mHeader("YUV4MPEG2 W16 H16 F1:10", "ok.y4m").fpsDenominator, 10);
    EXPECT_EQ(parseY4mHeader("YUV4MPEG2 W16 H16 F1000:1", "ok.y4m").fpsNumerator, 1000);
    EXPECT_EQ(parseY4mHeader("YUV4MPEG2 W16 H16 F30000:1001", "ok.y4m").fpsNumerator, 30000);
}

} // namespace
} // namespace lumar::test
