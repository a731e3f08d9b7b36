// The libcamera backend's buffer path without a camera: frame buffers backed by memfds stand
// in for the pipeline's dmabufs (both are mmap()able file descriptors), so the mapping, the
// layout checks and the conversion run exactly as on a camera's buffers. The converted pixels
// are compared with the BT.601/709 equations evaluated in double precision.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <memory>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <libcamera/formats.h>
#include <libcamera/framebuffer.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>

#include "capture/libcamera/dmabuf_mapping.h"
#include "capture/libcamera/libcamera_buffer.h"
#include "capture/libcamera/libcamera_frame.h"
#include "core/error.h"
#include "core/unique_fd.h"

namespace lumar {
namespace {

// A memfd holding `bytes`, as the pipeline's dmabuf would.
UniqueFd memfdWith(const std::vector<uint8_t>& bytes)
{
    UniqueFd fd(::memfd_create("lumar-libcamera-test", MFD_CLOEXEC));
    EXPECT_TRUE(fd.valid());
    EXPECT_EQ(::write(fd.get(), bytes.data(), bytes.size()), ssize_t(bytes.size()));
    return fd;
}

// One frame buffer whose planes (offset, length) all live in `fd`.
std::unique_ptr<libcamera::FrameBuffer> bufferOf(const UniqueFd& fd,
                                                 const std::vector<std::pair<unsigned, unsigned>>& planes)
{
    std::vector<libcamera::FrameBuffer::Plane> described;
    for (const auto& [offset, length] : planes) {
        libcamera::FrameBuffer::Plane plane;
        plane.fd = libcamera::SharedFD(fd.get()); // duplicates: the buffer owns its own copy
        plane.offset = offset;
        plane.length = length;
        described.push_back(plane);
    }
    return std::make_unique<libcamera::FrameBuffer>(described);
}

// Reference YCbCr → R'G'B' in double precision (ITU-R BT.601-7 / BT.709-6), clamped, unrounded.
std::array<double, 3> referenceRgb(int y, int cb, int cr, YCbCrColorimetry c)
{
    const double kr = c.matrix == YCbCrMatrix::Bt709 ? 0.2126 : 0.299;
    const double kb = c.matrix == YCbCrMatrix::Bt709 ? 0.0722 : 0.114;
    const double kg = 1.0 - kr - kb;
    const double yy = c.fullRange ? y : (y - 16) * 255.0 / 219.0;
    const double pb = c.fullRange ? cb - 128.0 : (cb - 128) * 255.0 / 224.0;
    const double pr = c.fullRange ? cr - 128.0 : (cr - 128) * 255.0 / 224.0;
    const double r = yy + 2.0 * (1.0 - kr) * pr;
    const double b = yy + 2.0 * (1.0 - kb) * pb;
    const double g = (yy - kr * r - kb * b) / kg;
    return {std::clamp(r, 0.0, 255.0), std::clamp(g, 0.0, 255.0), std::clamp(b, 0.0, 255.0)};
}

// A varied but deterministic test image: every Y, Cb, Cr value range is touched.
uint8_t lumaAt(int x, int y)
{
    return uint8_t((x * 7 + y * 13) % 256);
}
uint8_t cbAt(int cx, int cy)
{
    return uint8_t((cx * 29 + cy * 3 + 40) % 256);
}
uint8_t crAt(int cx, int cy)
{
    return uint8_t((cx * 5 + cy * 31 + 200) % 256);
}

constexpr int kWidth = 64;
constexpr int kHeight = 32;

// Largest difference between the frame and the reference, in code values, over all pixels.
// `chroma(x, y)` gives the (Cb, Cr) that covers pixel (x, y) in the tested layout.
template <typename Chroma> double worstError(const Frame& frame, YCbCrColorimetry colorimetry, Chroma chroma)
{
    double worst = 0.0;
    for (int y = 0; y < kHeight; ++y) {
        for (int x = 0; x < kWidth; ++x) {
            const auto [cb, cr] = chroma(x, y);
            const auto expected = referenceRgb(lumaAt(x, y), cb, cr, colorimetry);
            const uint8_t* got = frame.rgb.row(y) + x * 3;
            for (int c = 0; c < 3; ++c) {
                worst = std::max(worst, std::abs(got[c] - expected[size_t(c)]));
            }
            const double expectedLuma = std::clamp(
                colorimetry.fullRange ? double(lumaAt(x, y)) : (lumaAt(x, y) - 16) * 255.0 / 219.0, 0.0, 255.0);
            worst = std::max(worst, std::abs(frame.luma.row(y)[x] - expectedLuma));
        }
    }
    return worst;
}

// NV12 with padded rows (stride 96 for 64 pixels), luma then interleaved chroma.
std::vector<uint8_t> nv12Bytes(size_t stride)
{
    std::vector<uint8_t> bytes(stride * kHeight * 3 / 2, 0xee); // padding is garbage
    for (int y = 0; y < kHeight; ++y)
        for (int x = 0; x < kWidth; ++x)
            bytes[size_t(y) * stride + size_t(x)] = lumaAt(x, y);
    uint8_t* uv = bytes.data() + stride * kHeight;
    for (int cy = 0; cy < kHeight / 2; ++cy) {
        for (int cx = 0; cx < kWidth / 2; ++cx) {
            uv[size_t(cy) * stride + size_t(cx) * 2] = cbAt(cx, cy);
            uv[size_t(cy) * stride + size_t(cx) * 2 + 1] = crAt(cx, cy);
        }
    }
    return bytes;
}

std::pair<int, int> nv12Chroma(int x, int y)
{
    return {cbAt(x / 2, y / 2), crAt(x / 2, y / 2)};
}

TEST(LibcameraFrame, Nv12InTwoPlanesOfOneDmabuf)
{
    const size_t stride = 96;
    const UniqueFd fd = memfdWith(nv12Bytes(stride));
    const unsigned lumaBytes = unsigned(stride * kHeight);
    const auto buffer = bufferOf(fd, {{0, lumaBytes}, {lumaBytes, lumaBytes / 2}});
    const DmabufMapping mapping(*buffer);
    ASSERT_EQ(mapping.planeCount(), 2u);
    // One mapping for the shared dmabuf: the planes sit at their offsets within it.
    EXPECT_EQ(mapping.plane(1) - mapping.plane(0), std::ptrdiff_t(lumaBytes));

    const LibcameraLayout layout{libcamera::formats::NV12, kWidth, kHeight, stride};
    EXPECT_EQ(checkMappedImage(mapping, layout), "");
    EXPECT_EQ(imageBytes(layout), stride * kHeight * 3 / 2);
    for (const YCbCrColorimetry colorimetry :
         {YCbCrColorimetry{YCbCrMatrix::Bt601, false}, YCbCrColorimetry{YCbCrMatrix::Bt709, true}}) {
        Frame frame;
        convertLibcameraImage(mapping, layout, YCbCrConverter(colorimetry), frame);
        ASSERT_EQ(frame.rgb.width, kWidth);
        ASSERT_EQ(frame.rgb.height, kHeight);
        // 16.16 fixed point against double precision: within rounding (0.5) plus table error.
        EXPECT_LE(worstError(frame, colorimetry, nv12Chroma), 0.52);
    }
}

TEST(LibcameraFrame, Nv12AsOnePlaneFindsTheChromaAfterTheLuma)
{
    const size_t stride = 64;
    const UniqueFd fd = memfdWith(nv12Bytes(stride));
    const auto buffer = bufferOf(fd, {{0, unsigned(stride * kHeight * 3 / 2)}});
    const DmabufMapping mapping(*buffer);
    const LibcameraLayout layout{libcamera::formats::NV12, kWidth, kHeight, stride};
    ASSERT_EQ(checkMappedImage(mapping, layout), "");
    Frame frame;
    const YCbCrColorimetry colorimetry{};
    convertLibcameraImage(mapping, layout, YCbCrConverter(colorimetry), frame);
    EXPECT_LE(worstError(frame, colorimetry, nv12Chroma), 0.52);
}

TEST(LibcameraFrame, YuyvWithPaddedRows)
{
    const size_t stride = kWidth * 2 + 32;
    std::vector<uint8_t> bytes(stride * kHeight, 0x11);
    for (int y = 0; y < kHeight; ++y) {
        for (int x = 0; x < kWidth; x += 2) {
            uint8_t* p = bytes.data() + size_t(y) * stride + size_t(x) * 2;
            p[0] = lumaAt(x, y);
            p[1] = cbAt(x / 2, y);
            p[2] = lumaAt(x + 1, y);
            p[3] = crAt(x / 2, y);
        }
    }
    const UniqueFd fd = memfdWith(bytes);
    const auto buffer = bufferOf(fd, {{0, unsigned(bytes.size())}});
    const DmabufMapping mapping(*buffer);
    const LibcameraLayout layout{libcamera::formats::YUYV, kWidth, kHeight, stride};
    ASSERT_EQ(checkMappedImage(mapping, layout), "");
    Frame frame;
    const YCbCrColorimetry colorimetry{YCbCrMatrix::Bt709, false};
    convertLibcameraImage(mapping, layout, YCbCrConverter(colorimetry), frame);
    EXPECT_LE(worstError(frame, colorimetry,
                         [](int x, int y) {
                             return std::pair<int, int>{cbAt(x / 2, y), crAt(x / 2, y)};
                         }),
              0.52);
}

TEST(LibcameraFrame, ShortOrUnusableBuffersAreReported)
{
    const size_t stride = 64;
    const UniqueFd fd = memfdWith(nv12Bytes(stride));
    const unsigned lumaBytes = unsigned(stride * kHeight);
    const LibcameraLayout layout{libcamera::formats::NV12, kWidth, kHeight, stride};
    // The chroma plane one byte short.
    const auto shortChroma = bufferOf(fd, {{0, lumaBytes}, {lumaBytes, lumaBytes / 2 - 1}});
    EXPECT_NE(checkMappedImage(DmabufMapping(*shortChroma), layout).find("chroma plane holds 1023 bytes"),
              std::string::npos);
    // A single plane holding only the luma.
    const auto lumaOnly = bufferOf(fd, {{0, lumaBytes}});
    EXPECT_NE(checkMappedImage(DmabufMapping(*lumaOnly), layout), "");
    // A stride narrower than a row; an odd width; a format lumar does not convert.
    const auto whole = bufferOf(fd, {{0, lumaBytes * 3 / 2}});
    const DmabufMapping mapping(*whole);
    EXPECT_NE(checkMappedImage(mapping, {libcamera::formats::NV12, kWidth, kHeight, 32}).find("stride 32"),
              std::string::npos);
    EXPECT_NE(checkMappedImage(mapping, {libcamera::formats::NV12, kWidth - 1, kHeight, stride}), "");
    EXPECT_NE(checkMappedImage(mapping, {libcamera::formats::MJPEG, kWidth, kHeight, stride}).find("MJPEG"),
              std::string::npos);
}

TEST(LibcameraFrame, PlaneWithoutADmabufIsARuntimeError)
{
    libcamera::FrameBuffer::Plane plane;
    plane.offset = 0;
    plane.length = 4096; // fd left invalid
    const libcamera::FrameBuffer buffer({plane});
    EXPECT_THROW(DmabufMapping{buffer}, RuntimeError);
}

TEST(LibcameraFrame, FormatPreferenceIsNv12ThenYuyvThenPackedRgb)
{
    using namespace libcamera::formats;
    EXPECT_EQ(chooseLibcameraFormat({YUYV, MJPEG, NV12}), NV12);
    EXPECT_EQ(chooseLibcameraFormat({MJPEG, YUYV, RGB888}), YUYV);
    EXPECT_EQ(chooseLibcameraFormat({BGR888, RGB888, NV12}), NV12);
    // vimc (libcamera 0.0.3) offers only these two; BGR888 is its default.
    EXPECT_EQ(chooseLibcameraFormat({RGB888, BGR888}), BGR888);
    EXPECT_EQ(chooseLibcameraFormat({RGB888, BGR888}, libcameraFormatFromName("auto")), BGR888);
    EXPECT_EQ(chooseLibcameraFormat({MJPEG, RGB888}), RGB888);
    EXPECT_EQ(chooseLibcameraFormat({XRGB8888, XBGR8888}), XBGR8888);
    EXPECT_EQ(chooseLibcameraFormat({XRGB8888, RGB888}), RGB888); // 3 bytes a pixel before 4
    EXPECT_EQ(chooseLibcameraFormat({MJPEG, XRGB8888}), XRGB8888);
    // Other RGB layouts (16-bit, alpha-first words) are not converted.
    EXPECT_FALSE(chooseLibcameraFormat({MJPEG, RGB565, ARGB8888, RGBA8888}).isValid());
    EXPECT_FALSE(chooseLibcameraFormat({}).isValid());
    // A required YCbCr format an RGB-only camera lacks is none, as for any other camera.
    EXPECT_FALSE(chooseLibcameraFormat({RGB888, BGR888}, YUYV).isValid());

    for (const libcamera::PixelFormat& format : {RGB888, BGR888, XRGB8888, XBGR8888}) {
        EXPECT_TRUE(isConvertibleLibcameraFormat(format)) << format.toString();
        EXPECT_TRUE(isPackedRgbLibcameraFormat(format)) << format.toString();
    }
    for (const libcamera::PixelFormat& format : {NV12, YUYV, MJPEG, RGB565}) {
        EXPECT_FALSE(isPackedRgbLibcameraFormat(format)) << format.toString();
    }
}

TEST(LibcameraFrame, NoConvertibleFormatMessageListsWhatLumarConverts)
{
    using namespace libcamera::formats;
    EXPECT_EQ(convertibleLibcameraFormatNames(), "NV12, YUYV, BGR888, RGB888, XBGR8888, XRGB8888");
    EXPECT_EQ(noConvertibleFormatReason({MJPEG, RGB565}, {}),
              "has no viewfinder format lumar converts (offers MJPEG, RGB565; lumar converts NV12, YUYV, BGR888, "
              "RGB888, XBGR8888, XRGB8888)");
    EXPECT_EQ(noConvertibleFormatReason({RGB888, BGR888}, YUYV),
              "does not offer camera.format YUYV (offers RGB888, BGR888; lumar converts NV12, YUYV, BGR888, RGB888, "
              "XBGR8888, XRGB8888)");
    EXPECT_EQ(noConvertibleFormatReason({}, {}),
              "has no viewfinder format lumar converts (offers none; lumar converts NV12, YUYV, BGR888, RGB888, "
              "XBGR8888, XRGB8888)");
}

TEST(LibcameraFrame, ConfiguredFormatIsTakenWhenOfferedAndOnlyThen)
{
    using namespace libcamera::formats;
    EXPECT_FALSE(libcameraFormatFromName("auto").isValid());
    EXPECT_EQ(libcameraFormatFromName("nv12"), NV12);
    EXPECT_EQ(libcameraFormatFromName("yuyv"), YUYV);
    for (const char* name : {"mjpeg", "grey", "rgb"}) {
        try {
            libcameraFormatFromName(name);
            ADD_FAILURE() << name << " accepted";
        } catch (const InputError& e) {
            EXPECT_NE(std::string(e.what()).find(std::string("camera.format: '") + name + "'"), std::string::npos)
                << e.what();
        }
    }
    // Required YUYV wins over the preferred NV12; a required format the camera lacks is none.
    EXPECT_EQ(chooseLibcameraFormat({NV12, YUYV}, YUYV), YUYV);
    EXPECT_FALSE(chooseLibcameraFormat({NV12, MJPEG}, YUYV).isValid());
    EXPECT_EQ(chooseLibcameraFormat({NV12, YUYV}, libcameraFormatFromName("auto")), NV12);
}

// The planes kept for the GPU: tightly packed copies of the buffer's rows (padding dropped),
// the stream's colorimetry, and the tracker's luma as the CPU conversion writes it.
TEST(LibcameraFrame, PlanesKeptForTheGpuAreTheBuffersRowsWithoutPadding)
{
    const size_t stride = 96;
    const std::vector<uint8_t> bytes = nv12Bytes(stride);
    const UniqueFd fd = memfdWith(bytes);
    const unsigned lumaBytes = unsigned(stride * kHeight);
    const auto buffer = bufferOf(fd, {{0, lumaBytes}, {lumaBytes, lumaBytes / 2}});
    const DmabufMapping mapping(*buffer);
    const LibcameraLayout layout{libcamera::formats::NV12, kWidth, kHeight, stride};
    const YCbCrColorimetry colorimetry{YCbCrMatrix::Bt709, true};
    const YCbCrConverter converter(colorimetry);
    Frame frame;
    keepLibcameraPlanes(mapping, layout, converter, frame);
    const YCbCrImage& raw = frame.ycbcr;
    ASSERT_EQ(raw.layout, YCbCrLayout::Nv12);
    EXPECT_EQ(raw.width, kWidth);
    EXPECT_EQ(raw.height, kHeight);
    EXPECT_EQ(raw.colorimetry.matrix, YCbCrMatrix::Bt709);
    EXPECT_TRUE(raw.colorimetry.fullRange);
    ASSERT_EQ(raw.stride0, size_t(kWidth));
    ASSERT_EQ(raw.stride1, size_t(kWidth));
    ASSERT_EQ(raw.plane0.size(), size_t(kWidth * kHeight));
    ASSERT_EQ(raw.plane1.size(), size_t(kWidth * kHeight / 2));
    for (int y = 0; y < kHeight; ++y)
        for (int x = 0; x < kWidth; ++x)
            ASSERT_EQ(raw.plane0[size_t(y * kWidth + x)], lumaAt(x, y)) << x << "," << y;
    for (int cy = 0; cy < kHeight / 2; ++cy)
        for (int cx = 0; cx < kWidth / 2; ++cx) {
            ASSERT_EQ(raw.plane1[size_t(cy * kWidth + cx * 2)], cbAt(cx, cy));
            ASSERT_EQ(raw.plane1[size_t(cy * kWidth + cx * 2 + 1)], crAt(cx, cy));
        }
    Frame converted;
    convertLibcameraImage(mapping, layout, converter, converted);
    EXPECT_EQ(frame.luma.data, converted.luma.data);

    // YUYV: one plane of 2 bytes per pixel.
    const size_t yuyvStride = kWidth * 2 + 16;
    std::vector<uint8_t> yuyv(yuyvStride * kHeight, 0x55);
    for (int y = 0; y < kHeight; ++y)
        for (int x = 0; x < kWidth * 2; ++x)
            yuyv[size_t(y) * yuyvStride + size_t(x)] = uint8_t(x + y);
    const UniqueFd yuyvFd = memfdWith(yuyv);
    const auto yuyvBuffer = bufferOf(yuyvFd, {{0, unsigned(yuyv.size())}});
    keepLibcameraPlanes(DmabufMapping(*yuyvBuffer), {libcamera::formats::YUYV, kWidth, kHeight, yuyvStride}, converter,
                        frame);
    ASSERT_EQ(frame.ycbcr.layout, YCbCrLayout::Yuyv);
    EXPECT_EQ(frame.ycbcr.stride0, size_t(kWidth * 2));
    EXPECT_TRUE(frame.ycbcr.plane1.empty());
    ASSERT_EQ(frame.ycbcr.plane0.size(), size_t(kWidth * 2 * kHeight));
    EXPECT_EQ(frame.ycbcr.plane0[size_t(5 * kWidth * 2 + 7)], uint8_t(7 + 5));
}

// Same file, same inode: `a` and `b` are descriptors of one memfd (or dmabuf).
bool sameFile(int a, int b)
{
    struct stat sa {};
    struct stat sb {};
    return ::fstat(a, &sa) == 0 && ::fstat(b, &sb) == 0 && sa.st_ino == sb.st_ino && sa.st_dev == sb.st_dev;
}

// A lent buffer describes its planes in memory and as dmabufs, and keeps both alive after the
// FrameBuffer (and the allocator's descriptors) are gone.
TEST(LibcameraFrame, LentBuffersDescribeTheirPlanesAndOutliveTheFrameBuffer)
{
    const size_t stride = 96;
    const unsigned lumaBytes = unsigned(stride * kHeight);
    const LibcameraLayout layout{libcamera::formats::NV12, kWidth, kHeight, stride};
    std::shared_ptr<LibcameraBuffer> twoPlanes;
    std::shared_ptr<LibcameraBuffer> onePlane;
    {
        const UniqueFd fd = memfdWith(nv12Bytes(stride));
        const auto buffer = bufferOf(fd, {{0, lumaBytes}, {lumaBytes, lumaBytes / 2}});
        twoPlanes = std::make_shared<LibcameraBuffer>(*buffer, DmabufMapping(*buffer), layout);
        const auto whole = bufferOf(fd, {{0, lumaBytes * 3 / 2}});
        onePlane = std::make_shared<LibcameraBuffer>(*whole, DmabufMapping(*whole), layout);
        for (const auto& lent : {twoPlanes, onePlane}) {
            EXPECT_TRUE(lent->exported());
            EXPECT_EQ(lent->drmFourcc(), libcamera::formats::NV12.fourcc());
            const auto& planes = lent->planes();
            EXPECT_TRUE(sameFile(planes[0].dmabufFd, fd.get()));
            EXPECT_NE(planes[0].dmabufFd, fd.get());           // its own descriptor
            EXPECT_EQ(planes[1].dmabufFd, planes[0].dmabufFd); // one dmabuf, duplicated once
            EXPECT_EQ(planes[0].offset, 0u);
            EXPECT_EQ(planes[1].offset, lumaBytes);
            EXPECT_EQ(planes[0].size, lumaBytes);
            EXPECT_EQ(planes[1].size, lumaBytes / 2);
            EXPECT_EQ(planes[1].data - planes[0].data, std::ptrdiff_t(lumaBytes));
        }
    } // the memfd and both FrameBuffers are gone here
    for (const auto& lent : {twoPlanes, onePlane}) {
        const auto& planes = lent->planes();
        EXPECT_EQ(planes[0].data[size_t(5) * stride + 7], lumaAt(7, 5));
        EXPECT_EQ(planes[1].data[size_t(3) * stride + 2 * 4], cbAt(4, 3));
        uint8_t byte = 0;
        ASSERT_EQ(::pread(planes[1].dmabufFd, &byte, 1, off_t(lumaBytes + 3 * stride + 2 * 4 + 1)), 1);
        EXPECT_EQ(byte, crAt(4, 3));
    }
}

TEST(LibcameraFrame, ColorimetryFollowsTheStreamsColourSpace)
{
    const auto check = [](const std::optional<libcamera::ColorSpace>& space, YCbCrMatrix matrix, bool fullRange) {
        const YCbCrColorimetry c = colorimetryOfColorSpace(space);
        EXPECT_EQ(c.matrix, matrix) << libcamera::ColorSpace::toString(space);
        EXPECT_EQ(c.fullRange, fullRange) << libcamera::ColorSpace::toString(space);
    };
    check(std::nullopt, YCbCrMatrix::Bt601, false); // unknown: BT.601 limited
    check(libcamera::ColorSpace::Smpte170m, YCbCrMatrix::Bt601, false);
    check(libcamera::ColorSpace::Sycc, YCbCrMatrix::Bt601, true); // JPEG-style full range
    check(libcamera::ColorSpace::Rec709, YCbCrMatrix::Bt709, false);
    check(libcamera::ColorSpace::Rec2020, YCbCrMatrix::Bt709, false); // the closer matrix
    check(libcamera::ColorSpace::Srgb, YCbCrMatrix::Bt601, true);     // sRGB: no YCbCr encoding, full range
    libcamera::ColorSpace fullRec709 = libcamera::ColorSpace::Rec709;
    fullRec709.range = libcamera::ColorSpace::Range::Full;
    check(fullRec709, YCbCrMatrix::Bt709, true);
}

// Packed RGB: a test image whose red, green and blue differ at every pixel (so a swapped
// channel cannot pass), an odd width (RGB has no chroma pairs), rows padded with garbage.
constexpr int kRgbWidth = 37;
constexpr int kRgbHeight = 11;

std::array<uint8_t, 3> rgbAt(int x, int y)
{
    return {uint8_t((x * 7 + y * 3 + 1) % 256), uint8_t((x * 11 + y * 17 + 90) % 256),
            uint8_t((x * 5 + y * 29 + 170) % 256)};
}

// The bytes of one pixel as drm_fourcc.h defines the format: the name gives the components
// from the most significant end of a little-endian word ("[23:0] R:G:B little endian" for
// RGB888, "[31:0] x:R:G:B" for XRGB8888), written here as that word and stored byte by byte.
std::vector<uint8_t> drmPixelBytes(const libcamera::PixelFormat& format, std::array<uint8_t, 3> rgb, uint8_t filler)
{
    using namespace libcamera::formats;
    const uint32_t r = rgb[0], g = rgb[1], b = rgb[2];
    uint32_t word = 0;
    size_t bytes = 3;
    if (format == RGB888) {
        word = r << 16 | g << 8 | b;
    } else if (format == BGR888) {
        word = b << 16 | g << 8 | r;
    } else if (format == XRGB8888) {
        word = uint32_t(filler) << 24 | r << 16 | g << 8 | b;
        bytes = 4;
    } else if (format == XBGR8888) {
        word = uint32_t(filler) << 24 | b << 16 | g << 8 | r;
        bytes = 4;
    } else {
        ADD_FAILURE() << "no DRM layout for " << format.toString();
    }
    std::vector<uint8_t> out;
    for (size_t i = 0; i < bytes; ++i)
        out.push_back(uint8_t(word >> (8 * i))); // little endian: least significant byte first
    return out;
}

std::vector<uint8_t> packedRgbBytes(const libcamera::PixelFormat& format, size_t stride)
{
    std::vector<uint8_t> bytes(stride * kRgbHeight, 0xee); // the padding is garbage
    for (int y = 0; y < kRgbHeight; ++y) {
        size_t at = size_t(y) * stride;
        for (int x = 0; x < kRgbWidth; ++x) {
            for (const uint8_t byte : drmPixelBytes(format, rgbAt(x, y), uint8_t(0x5a + x)))
                bytes[at++] = byte;
        }
    }
    return bytes;
}

// The memory order spelled out once, as a check on drmPixelBytes itself: libcamera's RGB888
// is B, G, R in memory and BGR888 is R, G, B.
TEST(LibcameraFrame, DrmRgbNamesRunOppositeToTheBytesInMemory)
{
    using namespace libcamera::formats;
    const std::array<uint8_t, 3> rgb{10, 20, 30};
    EXPECT_EQ(drmPixelBytes(RGB888, rgb, 0), (std::vector<uint8_t>{30, 20, 10}));
    EXPECT_EQ(drmPixelBytes(BGR888, rgb, 0), (std::vector<uint8_t>{10, 20, 30}));
    EXPECT_EQ(drmPixelBytes(XRGB8888, rgb, 99), (std::vector<uint8_t>{30, 20, 10, 99}));
    EXPECT_EQ(drmPixelBytes(XBGR8888, rgb, 99), (std::vector<uint8_t>{10, 20, 30, 99}));
    // The fourccs are the DRM ones (drm_fourcc.h), which is what lets the names be read so.
    EXPECT_EQ(RGB888.fourcc(), uint32_t('R' | 'G' << 8 | '2' << 16 | '4' << 24));
    EXPECT_EQ(BGR888.fourcc(), uint32_t('B' | 'G' << 8 | '2' << 16 | '4' << 24));
}

TEST(LibcameraFrame, PackedRgbWithPaddedRowsBecomesExactRgbAndBt601Luma)
{
    using namespace libcamera::formats;
    for (const libcamera::PixelFormat& format : {RGB888, BGR888, XRGB8888, XBGR8888}) {
        SCOPED_TRACE(format.toString());
        const size_t bytesPerPixel = format == RGB888 || format == BGR888 ? 3 : 4;
        const size_t stride = kRgbWidth * bytesPerPixel + 13; // padded, and not a multiple of the pixel size
        const std::vector<uint8_t> bytes = packedRgbBytes(format, stride);
        const UniqueFd fd = memfdWith(bytes);
        const auto buffer = bufferOf(fd, {{0, unsigned(bytes.size())}});
        const DmabufMapping mapping(*buffer);
        const LibcameraLayout layout{format, kRgbWidth, kRgbHeight, stride};
        ASSERT_EQ(checkMappedImage(mapping, layout), "");
        EXPECT_EQ(imageBytes(layout), stride * kRgbHeight);

        Frame frame;
        frame.ycbcr.layout = YCbCrLayout::Nv12; // stale from an earlier frame
        // The converter is for YCbCr only; a limited-range one must not touch RGB values.
        keepLibcameraPlanes(mapping, layout, YCbCrConverter(YCbCrColorimetry{}), frame);
        EXPECT_TRUE(frame.ycbcr.empty()); // nothing kept for the GPU: the RGB image is the frame
        ASSERT_EQ(frame.rgb.width, kRgbWidth);
        ASSERT_EQ(frame.rgb.height, kRgbHeight);
        ASSERT_EQ(frame.rgb.channels, 3);
        ASSERT_EQ(frame.luma.width, kRgbWidth);
        ASSERT_EQ(frame.luma.height, kRgbHeight);
        ASSERT_EQ(frame.luma.channels, 1);
        double worstLuma = 0.0;
        for (int y = 0; y < kRgbHeight; ++y) {
            for (int x = 0; x < kRgbWidth; ++x) {
                const auto [r, g, b] = rgbAt(x, y);
                const uint8_t* got = frame.rgb.at(x, y);
                ASSERT_EQ(got[0], r) << x << "," << y;
                ASSERT_EQ(got[1], g) << x << "," << y;
                ASSERT_EQ(got[2], b) << x << "," << y;
                // BT.601 luma weights in double precision; the frame's value is it rounded.
                const double luma = 0.299 * r + 0.587 * g + 0.114 * b;
                worstLuma = std::max(worstLuma, std::abs(frame.luma.row(y)[x] - luma));
            }
        }
        EXPECT_LE(worstLuma, 0.5 + 1e-9);

        Frame converted;
        convertLibcameraImage(mapping, layout, YCbCrConverter(YCbCrColorimetry{YCbCrMatrix::Bt709, true}), converted);
        EXPECT_EQ(converted.rgb.data, frame.rgb.data);
        EXPECT_EQ(converted.luma.data, frame.luma.data);
    }
}

TEST(LibcameraFrame, PrimariesOfPackedRgbLandInTheirChannels)
{
    using namespace libcamera::formats;
    // One row: pure red, green, blue, white; RGB888's bytes are B, G, R.
    const std::vector<uint8_t> bytes{0, 0, 255, 0, 255, 0, 255, 0, 0, 255, 255, 255};
    const UniqueFd fd = memfdWith(bytes);
    const auto buffer = bufferOf(fd, {{0, unsigned(bytes.size())}});
    const DmabufMapping mapping(*buffer);
    Frame frame;
    convertLibcameraImage(mapping, {RGB888, 4, 1, 12}, YCbCrConverter(YCbCrColorimetry{}), frame);
    EXPECT_EQ(frame.rgb.data, (std::vector<uint8_t>{255, 0, 0, 0, 255, 0, 0, 0, 255, 255, 255, 255}));
    // round(0.299 * 255) = 76, round(0.587 * 255) = 150, round(0.114 * 255) = 29.
    EXPECT_EQ(frame.luma.data, (std::vector<uint8_t>{76, 150, 29, 255}));
    // The same bytes read as BGR888 (R, G, B in memory) are the other way round.
    convertLibcameraImage(mapping, {BGR888, 4, 1, 12}, YCbCrConverter(YCbCrColorimetry{}), frame);
    EXPECT_EQ(frame.rgb.data, (std::vector<uint8_t>{0, 0, 255, 0, 255, 0, 255, 0, 0, 255, 255, 255}));
    EXPECT_EQ(frame.luma.data, (std::vector<uint8_t>{29, 150, 76, 255}));
}

TEST(LibcameraFrame, PackedRgbBufferSizesAreChecked)
{
    using namespace libcamera::formats;
    const size_t stride = kRgbWidth * 3 + 13;
    const std::vector<uint8_t> bytes = packedRgbBytes(BGR888, stride);
    const UniqueFd fd = memfdWith(bytes);
    const auto whole = bufferOf(fd, {{0, unsigned(bytes.size())}});
    const DmabufMapping mapping(*whole);
    // An odd width is fine for RGB (it is not for YUYV).
    EXPECT_EQ(checkMappedImage(mapping, {BGR888, kRgbWidth, kRgbHeight, stride}), "");
    EXPECT_NE(checkMappedImage(mapping, {YUYV, kRgbWidth, kRgbHeight, stride}), "");
    // One byte short of stride x height.
    const auto shortBuffer = bufferOf(fd, {{0, unsigned(bytes.size() - 1)}});
    EXPECT_EQ(checkMappedImage(DmabufMapping(*shortBuffer), {RGB888, kRgbWidth, kRgbHeight, stride}),
              "plane 0 holds " + std::to_string(bytes.size() - 1) + " bytes, the image needs " +
                  std::to_string(bytes.size()));
    // A row narrower than its pixels: 3 bytes each for RGB888, 4 for XRGB8888.
    EXPECT_NE(checkMappedImage(mapping, {RGB888, kRgbWidth, kRgbHeight, kRgbWidth * 3 - 1}).find("stride 110"),
              std::string::npos);
    EXPECT_EQ(checkMappedImage(mapping, {RGB888, kRgbWidth, kRgbHeight, kRgbWidth * 3}), "");
    EXPECT_NE(checkMappedImage(mapping, {XRGB8888, kRgbWidth, kRgbHeight, kRgbWidth * 4 - 1}), "");
    // 4 bytes a pixel need a bigger buffer than this BGR888 one for the same stride.
    EXPECT_EQ(checkMappedImage(mapping, {XBGR8888, kRgbWidth, kRgbHeight, kRgbWidth * 4}).rfind("plane 0 holds", 0),
              0u);
    EXPECT_NE(checkMappedImage(mapping, {BGR888, 0, kRgbHeight, stride}), "");
}

// RGB buffers are never lent; should one be described all the same, it names no DRM format,
// so the renderer cannot import it as a YCbCr frame.
TEST(LibcameraFrame, PackedRgbBuffersDescribeNoDrmFormatForLending)
{
    const size_t stride = kRgbWidth * 3;
    const std::vector<uint8_t> bytes = packedRgbBytes(libcamera::formats::RGB888, stride);
    const UniqueFd fd = memfdWith(bytes);
    const auto buffer = bufferOf(fd, {{0, unsigned(bytes.size())}});
    const LibcameraBuffer lent(*buffer, DmabufMapping(*buffer),
                               {libcamera::formats::RGB888, kRgbWidth, kRgbHeight, stride});
    EXPECT_EQ(lent.drmFourcc(), 0u);
    EXPECT_FALSE(lent.exported());
    EXPECT_EQ(lent.planes()[0].size, bytes.size());
    EXPECT_EQ(lent.planes()[1].data, nullptr);
    EXPECT_EQ(lent.mapping().plane(0)[0], rgbAt(0, 0)[2]); // RGB888's first byte is blue
}

} // namespace
} // namespace lumar
