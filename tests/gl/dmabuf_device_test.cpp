// Zero-copy import for real: frames in dmabufs of the DRM device the EGL display renders with
// (its dumb buffers, exported with PRIME), imported through EGL_EXT_image_dma_buf_import and
// drawn by the background pass, against the CPU converter. Where the import path of
// dmabuf_image.h is exercised end to end on a kernel: the texture must be the buffer (a write
// to the buffer shows in the next draw with no new import), every layout, matrix and range
// must convert as the uploaded planes do, and a camera's buffers must be refused where the
// driver could not read them.
// Runs where the display names its DRM device and that device makes dumb buffers: in the
// virtual board (Mesa's kms_swrast on vgem, scripts/virtual-board.sh) and on GPUs with a KMS
// node. Here (plain swrast, no DRM device) it skips, saying why.
#include <chrono>
#include <cstdio>
#include <cstring>
#include <random>
#include <string>
#include <vector>

#include <GLES3/gl3.h>
#include <fcntl.h>
#include <gtest/gtest.h>
#include <linux/videodev2.h>
#include <sys/mman.h>
#include <xf86drm.h>

#include "capture/v4l2/v4l2_buffer.h"
#include "core/error.h"
#include "core/unique_fd.h"
#include "gles_renderer/display/drm_device.h"
#include "gles_renderer/gl/dmabuf_image.h"
#include "gles_renderer/gl/egl_context.h"
#include "gles_renderer/gl/frame_readback.h"
#include "gles_renderer/gl/render_target.h"
#include "gles_renderer/scene/background_pass.h"
#include "ycbcr_test_frames.h"

namespace lumar {
namespace {

// Even, and rows padded to a stride that is not a multiple of 4 (NV12).
constexpr int kWidth = 322;
constexpr int kHeight = 202;
constexpr size_t kPadding = 6;

using Case = test::YcbcrCase;

// The display, a context on it and its DRM device, or why this machine cannot run the tests.
struct Device {
    std::shared_ptr<EglDisplay> display;
    std::unique_ptr<EglContext> context;
    UniqueFd drm;
    std::string skip;
};

// A dumb buffer's handle, closed when it goes (the buffer lives on while a dmabuf or mapping
// of it does).
struct DumbHandle {
    int drm;
    uint32_t handle;
    DumbHandle(int drmFd, uint32_t dumbHandle) : drm(drmFd), handle(dumbHandle) {}
    DumbHandle(const DumbHandle&) = delete;
    DumbHandle& operator=(const DumbHandle&) = delete;
    ~DumbHandle()
    {
        drm_mode_destroy_dumb destroy{};
        destroy.handle = handle;
        drmIoctl(drm, DRM_IOCTL_MODE_DESTROY_DUMB, &destroy);
    }
};

// The DRM node the display renders with: what EGL says (EGL_EXT_device_drm), else, for
// kms_swrast, which Mesa's surfaceless platform runs only on a vgem or virtio-gpu node
// (platform_surfaceless.c) and reports as a software device, the first such node.
std::string renderDeviceNode(const EglDisplay& display)
{
    if (!display.drmDeviceFile().empty() || display.driverName() != "kms_swrast")
        return display.drmDeviceFile();
    for (int minor = 0; minor < 16; ++minor) {
        const std::string node = "/dev/dri/card" + std::to_string(minor);
        const UniqueFd fd(::open(node.c_str(), O_RDWR | O_CLOEXEC));
        if (!fd.valid())
            continue;
        const std::string name = drmDriverName(fd.get());
        if (name == "vgem" || name == "virtio_gpu")
            return node;
    }
    return {};
}

Device openDevice()
{
    Device device;
    try {
        device.display = EglDisplay::surfaceless();
        device.context = std::make_unique<EglContext>(device.display);
        device.context->makeCurrent();
    } catch (const RuntimeError& e) {
        device.skip = std::string("no GLES 3 context: ") + e.what();
        return device;
    }
    const std::string driver = device.display->driverName().empty() ? "?" : device.display->driverName();
    const std::string node = renderDeviceNode(*device.display);
    if (node.empty()) {
        device.skip = "the EGL display (driver " + driver + ") renders with no DRM device";
        return device;
    }
    if (!device.display->hasExtension("EGL_EXT_image_dma_buf_import")) {
        device.skip = "the EGL display (driver " + driver + " on " + node + ") has no EGL_EXT_image_dma_buf_import";
        return device;
    }
    device.drm = UniqueFd(::open(node.c_str(), O_RDWR | O_CLOEXEC));
    if (!device.drm.valid()) {
        device.skip = "cannot open " + node + ": " + std::strerror(errno);
        return device;
    }
    // A small dumb buffer tells whether the device makes them (DRM_CAP_DUMB_BUFFER cannot:
    // render-only drivers such as vgem make dumb buffers but answer no capability query).
    drm_mode_create_dumb probe{};
    probe.width = probe.height = 16;
    probe.bpp = 8;
    if (drmIoctl(device.drm.get(), DRM_IOCTL_MODE_CREATE_DUMB, &probe) != 0) {
        device.skip =
            node + " (driver " + drmDriverName(device.drm.get()) + ") makes no dumb buffers: " + std::strerror(errno);
        return device;
    }
    const DumbHandle probeHandle{device.drm.get(), probe.handle};
    return device;
}

#define LUMAR_DEVICE_OR_SKIP(device)                                                                                   \
    const Device device = openDevice();                                                                                \
    if (!device.skip.empty())                                                                                          \
        GTEST_SKIP() << device.skip;

// A dumb buffer of `rows` rows of at least `minPitch` bytes, mapped for writing and exported
// as a dmabuf: the buffer a camera would have filled, on the render device.
struct DumbFrame {
    std::shared_ptr<V4l2Buffer> buffer;
    uint8_t* bytes = nullptr; // the mapping, writable
    size_t pitch = 0;
};

DumbFrame makeDumbFrame(int drm, uint32_t pixelFormat, size_t minPitch, int rows)
{
    drm_mode_create_dumb create{};
    create.width = uint32_t(minPitch);
    create.height = uint32_t(rows);
    create.bpp = 8;
    if (drmIoctl(drm, DRM_IOCTL_MODE_CREATE_DUMB, &create) != 0)
        throw RuntimeError(std::string("DRM_IOCTL_MODE_CREATE_DUMB failed: ") + std::strerror(errno));
    // The dmabuf and the mapping keep the memory; the handle is not needed past the export.
    const DumbHandle handle{drm, create.handle};
    drm_mode_map_dumb map{};
    map.handle = create.handle;
    if (drmIoctl(drm, DRM_IOCTL_MODE_MAP_DUMB, &map) != 0)
        throw RuntimeError(std::string("DRM_IOCTL_MODE_MAP_DUMB failed: ") + std::strerror(errno));
    void* address = ::mmap(nullptr, size_t(create.size), PROT_READ | PROT_WRITE, MAP_SHARED, drm, off_t(map.offset));
    if (address == MAP_FAILED)
        throw RuntimeError(std::string("mmap of a dumb buffer failed: ") + std::strerror(errno));
    MappedRegion mapping(address, size_t(create.size));
    int fd = -1;
    if (drmPrimeHandleToFD(drm, create.handle, DRM_CLOEXEC | DRM_RDWR, &fd) != 0)
        throw RuntimeError(std::string("drmPrimeHandleToFD failed: ") + std::strerror(errno));
    DumbFrame frame;
    frame.bytes = static_cast<uint8_t*>(address);
    frame.pitch = create.pitch;
    frame.buffer = std::make_shared<V4l2Buffer>(std::move(mapping), UniqueFd(fd), pixelFormat, kHeight, create.pitch);
    return frame;
}

// Colour bars or random bytes, written into the buffer at its pitch as a driver would.
void fill(const DumbFrame& frame, const Case& c, bool random, unsigned seed)
{
    test::fillYcbcrFrame(c, random, seed, kWidth, kHeight, frame.pitch, frame.bytes);
}

YCbCrImage lentImage(const DumbFrame& frame, const Case& c)
{
    YCbCrImage image;
    image.layout = c.layout;
    image.width = kWidth;
    image.height = kHeight;
    image.colorimetry = c.colorimetry;
    image.stride0 = frame.pitch;
    image.stride1 = c.layout == YCbCrLayout::Nv12 ? frame.pitch : 0;
    image.buffer = frame.buffer;
    return image;
}

Image8 cpuReference(const DumbFrame& frame, const Case& c)
{
    return test::cpuYcbcrReference(c, frame.bytes, frame.pitch, kWidth, kHeight);
}

// The background pass drawing into its own target, read back as the renderer reads frames.
struct Pass {
    RenderTarget target{kWidth, kHeight, 1};
    BackgroundPass background{target};
    FrameReadback readback{target.readFramebuffer(), kWidth, kHeight};

    Image8 draw(const YCbCrImage& image)
    {
        target.bindForDrawing();
        background.draw(image);
        target.finishFrame();
        Image8 out;
        readback.read(out);
        return out;
    }
};

TEST(DmabufDeviceImport, EveryLayoutMatrixAndRangeMatchesTheCpuConverter)
{
    LUMAR_DEVICE_OR_SKIP(device);
    Pass pass;
    pass.background.enableDmabufImport(*device.display, DmabufOrigin::RenderDevice);
    ASSERT_TRUE(pass.background.dmabufImporter()->usable()) << pass.background.dmabufImporter()->unavailableReason();
    unsigned seed = 1;
    uint64_t draws = 0;
    for (const Case& c : test::allYcbcrCases()) {
        const bool nv12 = c.layout == YCbCrLayout::Nv12;
        const DumbFrame frame =
            makeDumbFrame(device.drm.get(), nv12 ? V4L2_PIX_FMT_NV12 : V4L2_PIX_FMT_YUYV,
                          size_t(kWidth) * (nv12 ? 1 : 2) + kPadding, nv12 ? kHeight * 3 / 2 : kHeight);
        for (bool random : {false, true}) {
            fill(frame, c, random, seed++);
            const Image8 out = pass.draw(lentImage(frame, c));
            ++draws;
            // Drawn from the import, not by the fallback upload.
            ASSERT_EQ(pass.background.importedFrames(), draws) << test::describe(c);
            const test::ByteDifference difference = test::compareBytes(out, cpuReference(frame, c));
            EXPECT_LE(difference.worst, 1) << test::describe(c) << (random ? " random" : " bars");
            EXPECT_LT(double(difference.differing), 0.001 * double(out.data.size()))
                << test::describe(c) << (random ? " random" : " bars");
        }
    }
    ASSERT_TRUE(pass.background.dmabufImporter()->usable()) << pass.background.dmabufImporter()->unavailableReason();
}

// Zero-copy means the texture is the buffer's memory: what the driver writes into a buffer it
// queued again shows in the next draw, through the import made the first time.
TEST(DmabufDeviceImport, TheTextureIsTheBufferItself)
{
    LUMAR_DEVICE_OR_SKIP(device);
    Pass pass;
    pass.background.enableDmabufImport(*device.display, DmabufOrigin::RenderDevice);
    const Case c{YCbCrLayout::Nv12, {YCbCrMatrix::Bt709, false}};
    const DumbFrame frame = makeDumbFrame(device.drm.get(), V4L2_PIX_FMT_NV12, kWidth, kHeight * 3 / 2);
    fill(frame, c, false, 0);
    const Image8 first = pass.draw(lentImage(frame, c));
    EXPECT_LE(test::compareBytes(first, cpuReference(frame, c)).worst, 1);
    fill(frame, c, true, 77); // the camera refilled the buffer
    const Image8 second = pass.draw(lentImage(frame, c));
    EXPECT_LE(test::compareBytes(second, cpuReference(frame, c)).worst, 1);
    EXPECT_GT(test::compareBytes(second, first).differing, second.data.size() / 2);
    EXPECT_EQ(pass.background.importedFrames(), 2u);
    EXPECT_EQ(pass.background.dmabufImporter()->importedBuffers(), 1u);

    // A per-frame figure for the notes (not asserted): the background drawn from the import
    // against the same lent buffer uploaded from its mapping (the fallback), GPU work included.
    Pass uploading;
    const auto time = [&](Pass& drawing) {
        constexpr int kDraws = 20;
        const YCbCrImage image = lentImage(frame, c);
        const auto start = std::chrono::steady_clock::now();
        for (int i = 0; i < kDraws; ++i) {
            drawing.target.bindForDrawing();
            drawing.background.draw(image);
            glFinish();
        }
        return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count() / kDraws;
    };
    const double imported = time(pass);
    const double uploaded = time(uploading);
    EXPECT_EQ(uploading.background.importedFrames(), 0u);
    std::printf("dmabuf import: %dx%d NV12 background in %.2f ms imported (0 copies), %.2f ms uploaded from the "
                "mapping (1 copy), driver %s\n",
                kWidth, kHeight, imported, uploaded, device.display->driverName().c_str());
}

// A camera's buffers come from another device; where the driver could not read them (kms_swrast)
// the importer must refuse them up front, so the frame is uploaded instead of crashing.
TEST(DmabufDeviceImport, ACamerasBuffersAreRefusedWhereTheDriverCannotReadThem)
{
    LUMAR_DEVICE_OR_SKIP(device);
    const DmabufImporter camera(*device.display);
    if (device.display->driverName() == "kms_swrast") {
        EXPECT_FALSE(camera.usable());
        EXPECT_NE(camera.unavailableReason().find("kms_swrast"), std::string::npos);
    } else {
        EXPECT_TRUE(camera.usable()) << camera.unavailableReason();
    }
    EXPECT_TRUE(DmabufImporter(*device.display, DmabufOrigin::RenderDevice).usable());
}

} // namespace
} // namespace lumar
