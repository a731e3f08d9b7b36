// The libcamera backend's buffer path without a camera: frame buffers backed by memfds stand
// in for the pipeline's dmabufs (both are mmap()able file descriptors), so the mapping, the
// layout checks and the conversion run exactly as on a camera's buffers. The converted pixels
// are compared with the BT.601/709 equations evaluated in double precision.
#include <algorithm>
#include <cmath>
#include <cstring>
#include <memory>
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

TEST(LibcameraFrame, FormatPreferenceIsNv12ThenYuyv)
{
    using namespace libcamera::formats;
    EXPECT_EQ(chooseLibcameraFormat({YUYV, MJPEG, NV12}), NV12);
    EXPECT_EQ(chooseLibcameraFormat({MJPEG, YUYV, RGB888}), YUYV);
    EXPECT_FALSE(chooseLibcameraFormat({MJPEG, RGB888}).isValid());
    EXPECT_FALSE(chooseLibcameraFormat({}).isValid());
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

} // namespace
} // namespace lumar
