// The GPU's YCbCr background (background_ycbcr.frag) against the CPU converter the capture
// thread uses (ycbcr_to_rgb): NV12 and YUYV, both matrices, both ranges, colour bars and
// random bytes (footroom/headroom excursions included), within one code value per channel;
// copied planes and lent (zero-copy) camera buffers alike.
#include <random>
#include <string>

#include <gtest/gtest.h>
#include <linux/videodev2.h>
#include <sys/mman.h>
#include <unistd.h>

#include "capture/v4l2/v4l2_buffer.h"
#include "capture/v4l2/ycbcr_to_rgb.h"
#include "core/error.h"
#include "gl_test_support.h"
#include "ycbcr_test_frames.h"

namespace lumar {
namespace {

// Even, but rows of the half-width RG8 plane are not 4-byte aligned; the padded stride is
// not a multiple of 4 either (the unpack row length must carry it).
constexpr int kWidth = 322;
constexpr int kHeight = 202;
constexpr size_t kPadding = 6;

using Case = test::YcbcrCase;

// A frame as the driver would deliver it: rows of `bytesPerLine`, NV12's chroma after Y.
struct DriverFrame {
    std::vector<uint8_t> bytes;
    size_t bytesPerLine = 0;
};

// Colour bars (the pattern's frame 3) or random bytes.
DriverFrame makeFrame(const Case& c, bool random, unsigned seed)
{
    DriverFrame frame;
    frame.bytesPerLine = size_t(kWidth) * (c.layout == YCbCrLayout::Nv12 ? 1 : 2) + kPadding;
    frame.bytes.resize(test::ycbcrFrameBytes(c, frame.bytesPerLine, kHeight));
    test::fillYcbcrFrame(c, random, random ? seed : 3, kWidth, kHeight, frame.bytesPerLine, frame.bytes.data());
    return frame;
}

// The renderer's input: the driver's planes with their padded strides.
YCbCrImage planesOf(const Case& c, const DriverFrame& frame)
{
    YCbCrImage image;
    image.layout = c.layout;
    image.width = kWidth;
    image.height = kHeight;
    image.colorimetry = c.colorimetry;
    const size_t planeSize = frame.bytesPerLine * size_t(kHeight);
    image.stride0 = frame.bytesPerLine;
    if (c.layout == YCbCrLayout::Nv12) {
        image.plane0.assign(frame.bytes.begin(), frame.bytes.begin() + std::ptrdiff_t(planeSize));
        image.plane1.assign(frame.bytes.begin() + std::ptrdiff_t(planeSize), frame.bytes.end());
        image.stride1 = frame.bytesPerLine;
    } else {
        image.plane0 = frame.bytes;
    }
    return image;
}

// The same frame lent rather than copied (zero-copy capture): the driver's bytes in a buffer
// the planes are read from in place, exported as the virtual camera does (a memfd standing in
// for the dmabuf). The renderer imports it where the display can, else uploads the mapping.
YCbCrImage lentPlanesOf(const Case& c, const DriverFrame& frame)
{
    YCbCrImage image;
    image.layout = c.layout;
    image.width = kWidth;
    image.height = kHeight;
    image.colorimetry = c.colorimetry;
    image.stride0 = frame.bytesPerLine;
    image.stride1 = c.layout == YCbCrLayout::Nv12 ? frame.bytesPerLine : 0;
    UniqueFd memfd(::memfd_create("lumar-lent-frame", MFD_CLOEXEC));
    EXPECT_TRUE(memfd.valid());
    EXPECT_EQ(::write(memfd.get(), frame.bytes.data(), frame.bytes.size()), ssize_t(frame.bytes.size()));
    void* address = ::mmap(nullptr, frame.bytes.size(), PROT_READ, MAP_SHARED, memfd.get(), 0);
    EXPECT_NE(address, MAP_FAILED);
    image.buffer = std::make_shared<V4l2Buffer>(MappedRegion(address, frame.bytes.size()), UniqueFd(::dup(memfd.get())),
                                                c.layout == YCbCrLayout::Nv12 ? V4L2_PIX_FMT_NV12 : V4L2_PIX_FMT_YUYV,
                                                kHeight, frame.bytesPerLine);
    return image;
}

Image8 cpuReference(const Case& c, const DriverFrame& frame)
{
    return test::cpuYcbcrReference(c, frame.bytes.data(), frame.bytesPerLine, kWidth, kHeight);
}

// Renders every case (colour bars, then random bytes) and compares with the CPU converter.
void expectMatchesCpu(SceneRenderer& renderer, bool lent = false)
{
    const CameraIntrinsics k = defaultIntrinsics(kWidth, kHeight);
    unsigned seed = 1;
    for (const Case& c : test::allYcbcrCases())
        for (bool random : {false, true}) {
            const DriverFrame frame = makeFrame(c, random, seed++);
            const Image8 expected = cpuReference(c, frame);
            Image8 out;
            renderer.render(lent ? lentPlanesOf(c, frame) : planesOf(c, frame), k, {});
            renderer.readback(out);
            ASSERT_EQ(out.width, kWidth);
            ASSERT_EQ(out.height, kHeight);
            ASSERT_EQ(out.channels, 3);
            const test::ByteDifference difference = test::compareBytes(out, expected);
            EXPECT_LE(difference.worst, 1) << test::describe(c) << (random ? " random" : " bars");
            // Rounding ties aside the two agree: most bytes are identical.
            EXPECT_LT(double(difference.differing), 0.001 * double(out.data.size()))
                << test::describe(c) << (random ? " random" : " bars");
        }
}

TEST(YcbcrBackground, MatchesTheCpuConverterInEveryLayoutMatrixAndRange)
{
    LUMAR_RENDERER_OR_SKIP(renderer, kWidth, kHeight);
    expectMatchesCpu(renderer);
}

// Zero-copy frames: read in place from the lent buffer (here, without
// EGL_EXT_image_dma_buf_import, by the plain upload) and drawn exactly like copied planes.
TEST(YcbcrBackground, LentCameraBuffersMatchTheCpuConverter)
{
    LUMAR_RENDERER_OR_SKIP(renderer, kWidth, kHeight);
    expectMatchesCpu(renderer, true);
}

// The renderer lets go of a lent buffer by the next frame (an imported one is held until the
// GPU has drawn it, an uploaded one not at all), so the capture source can queue it again.
TEST(YcbcrBackground, LentBuffersAreReleasedByTheNextFrame)
{
    LUMAR_RENDERER_OR_SKIP(renderer, kWidth, kHeight);
    const CameraIntrinsics k = defaultIntrinsics(kWidth, kHeight);
    const Case c{YCbCrLayout::Nv12, {}};
    std::weak_ptr<const CameraBuffer> first;
    {
        const YCbCrImage image = lentPlanesOf(c, makeFrame(c, false, 1));
        first = image.buffer;
        renderer.render(image, k, {});
    }
    Image8 out;
    renderer.render(lentPlanesOf(c, makeFrame(c, false, 2)), k, {});
    renderer.readback(out);
    EXPECT_TRUE(first.expired());
}

TEST(YcbcrBackground, MatchesTheCpuConverterWithMultisampling)
{
    RenderOptions options;
    options.samples = 4;
    LUMAR_RENDERER_OR_SKIP(renderer, kWidth, kHeight, options);
    expectMatchesCpu(renderer);
}

// The colour bars land where the pattern puts them: 75 % white in the first bar, 75 % blue
// in the seventh (BT.709 limited, YUYV), so the comparison above is not of two blank images.
TEST(YcbcrBackground, ColourBarsComeOutAtSeventyFivePercent)
{
    LUMAR_RENDERER_OR_SKIP(renderer, kWidth, kHeight);
    const Case c{YCbCrLayout::Yuyv, {YCbCrMatrix::Bt709, false}};
    Image8 out;
    renderer.render(planesOf(c, makeFrame(c, false, 0)), defaultIntrinsics(kWidth, kHeight), {});
    renderer.readback(out);
    const int barWidth = kWidth / 8;
    const uint8_t* white = out.at(barWidth / 2, kHeight / 4);
    const uint8_t* blue = out.at(6 * barWidth + barWidth / 2, kHeight / 4);
    for (int channel = 0; channel < 3; ++channel)
        EXPECT_NEAR(white[channel], 191, 2) << channel;
    EXPECT_NEAR(blue[0], 0, 2);
    EXPECT_NEAR(blue[1], 0, 2);
    EXPECT_NEAR(blue[2], 191, 2);
}

TEST(YcbcrBackground, WrongSizeOrShortPlanesAreInputErrors)
{
    LUMAR_RENDERER_OR_SKIP(renderer, kWidth, kHeight);
    const CameraIntrinsics k = defaultIntrinsics(kWidth, kHeight);
    const Case c{YCbCrLayout::Nv12, {}};
    YCbCrImage image = planesOf(c, makeFrame(c, true, 9));
    image.width = kWidth - 2;
    EXPECT_THROW(renderer.render(image, k, {}), InputError);
    image.width = kWidth;
    image.plane1.resize(image.plane1.size() / 2);
    EXPECT_THROW(renderer.render(image, k, {}), InputError);
    EXPECT_THROW(renderer.render(YCbCrImage{}, k, {}), InputError);
}

} // namespace
} // namespace lumar
