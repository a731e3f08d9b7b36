// Zero-copy camera frames in the renderer (gles_renderer/gl/dmabuf_image.h): the EGL image each
// plane becomes, the decision whether a display can import at all, and the plain-upload
// fallback. Here (llvmpipe on the surfaceless platform) the display has no
// EGL_EXT_image_dma_buf_import, so the import itself cannot run: the tests check that this is
// detected and that lent buffers still render exactly. On a display that has the extension the
// same tests try importing a memfd (what the virtual camera exports), which is no dmabuf: the
// failure must be logged once and the frame still drawn by the upload.
#include <cstring>
#include <vector>

#include <drm_fourcc.h>
#include <gtest/gtest.h>
#include <linux/videodev2.h>
#include <sys/mman.h>
#include <unistd.h>

#include "capture/v4l2/v4l2_buffer.h"
#include "core/error.h"
#include "gles_renderer/gl/dmabuf_image.h"
#include "gles_renderer/gl/egl_context.h"

namespace lumar {
namespace {

// A buffer as the virtual camera exports it: `bytes` in a memfd, mapped, and a duplicate of the
// memfd standing in for the dmabuf.
std::shared_ptr<V4l2Buffer> memfdBuffer(const std::vector<uint8_t>& bytes, uint32_t pixelFormat, int height,
                                        size_t bytesPerLine)
{
    UniqueFd memfd(::memfd_create("lumar-dmabuf-test", MFD_CLOEXEC));
    EXPECT_TRUE(memfd.valid());
    EXPECT_EQ(::write(memfd.get(), bytes.data(), bytes.size()), ssize_t(bytes.size()));
    void* address = ::mmap(nullptr, bytes.size(), PROT_READ, MAP_SHARED, memfd.get(), 0);
    EXPECT_NE(address, MAP_FAILED);
    return std::make_shared<V4l2Buffer>(MappedRegion(address, bytes.size()), UniqueFd(::dup(memfd.get())), pixelFormat,
                                        height, bytesPerLine);
}

YCbCrImage lentImage(std::shared_ptr<V4l2Buffer> buffer, YCbCrLayout layout, int width, int height, size_t stride)
{
    YCbCrImage image;
    image.layout = layout;
    image.width = width;
    image.height = height;
    image.stride0 = stride;
    image.stride1 = layout == YCbCrLayout::Nv12 ? stride : 0;
    image.buffer = std::move(buffer);
    return image;
}

TEST(DmabufImport, Nv12IsALumaAndAHalfSizeChromaImageOfTheSameDmabuf)
{
    const int width = 64, height = 32;
    const size_t stride = 80; // padded rows
    const auto buffer = memfdBuffer(std::vector<uint8_t>(stride * height * 3 / 2), V4L2_PIX_FMT_NV12, height, stride);
    ASSERT_TRUE(buffer->exported());
    EXPECT_EQ(buffer->drmFourcc(), uint32_t(DRM_FORMAT_NV12));
    const DmabufImports imports = dmabufImportsFor(lentImage(buffer, YCbCrLayout::Nv12, width, height, stride));
    ASSERT_EQ(imports.count, 2);
    const DmabufPlaneImport& luma = imports.planes[0];
    const DmabufPlaneImport& chroma = imports.planes[1];
    EXPECT_EQ(luma.drmFormat, uint32_t(DRM_FORMAT_R8));
    EXPECT_EQ(luma.width, width);
    EXPECT_EQ(luma.height, height);
    EXPECT_EQ(luma.offset, 0u);
    EXPECT_EQ(luma.pitch, stride);
    EXPECT_EQ(chroma.drmFormat, uint32_t(DRM_FORMAT_GR88));
    EXPECT_EQ(chroma.width, width / 2);
    EXPECT_EQ(chroma.height, height / 2);
    EXPECT_EQ(chroma.offset, stride * height); // single-planar NV12: chroma after the luma rows
    EXPECT_EQ(chroma.pitch, stride);
    EXPECT_EQ(chroma.fd, luma.fd);
    EXPECT_EQ(luma.fd, buffer->planes()[0].dmabufFd);

    const std::vector<EGLint> attributes = dmabufImageAttributes(chroma, false);
    const std::vector<EGLint> expected{EGL_WIDTH,
                                       width / 2,
                                       EGL_HEIGHT,
                                       height / 2,
                                       EGL_LINUX_DRM_FOURCC_EXT,
                                       EGLint(DRM_FORMAT_GR88),
                                       EGL_DMA_BUF_PLANE0_FD_EXT,
                                       chroma.fd,
                                       EGL_DMA_BUF_PLANE0_OFFSET_EXT,
                                       EGLint(stride * height),
                                       EGL_DMA_BUF_PLANE0_PITCH_EXT,
                                       EGLint(stride),
                                       EGL_NONE};
    EXPECT_EQ(attributes, expected);
    // With the modifiers extension the plane says it is linear (modifier 0).
    const std::vector<EGLint> withModifier = dmabufImageAttributes(chroma, true);
    ASSERT_EQ(withModifier.size(), expected.size() + 4);
    EXPECT_EQ(withModifier[12], EGL_DMA_BUF_PLANE0_MODIFIER_LO_EXT);
    EXPECT_EQ(withModifier[13], 0);
    EXPECT_EQ(withModifier[14], EGL_DMA_BUF_PLANE0_MODIFIER_HI_EXT);
    EXPECT_EQ(withModifier[15], 0);
    EXPECT_EQ(withModifier.back(), EGL_NONE);
}

TEST(DmabufImport, YuyvIsOneImageOfPackedTexelsAndUnexportedBuffersNone)
{
    const int width = 64, height = 32;
    const size_t stride = 136;
    const auto buffer = memfdBuffer(std::vector<uint8_t>(stride * height), V4L2_PIX_FMT_YUYV, height, stride);
    const DmabufImports imports = dmabufImportsFor(lentImage(buffer, YCbCrLayout::Yuyv, width, height, stride));
    ASSERT_EQ(imports.count, 1);
    EXPECT_EQ(imports.planes[0].drmFormat, uint32_t(DRM_FORMAT_ABGR8888)); // bytes Y0 Cb Y1 Cr as R G B A
    EXPECT_EQ(imports.planes[0].width, width / 2);
    EXPECT_EQ(imports.planes[0].height, height);
    EXPECT_EQ(imports.planes[0].pitch, stride);

    // Copied planes, or a buffer the driver did not export: nothing to import.
    YCbCrImage copied;
    copied.layout = YCbCrLayout::Yuyv;
    copied.width = width;
    copied.height = height;
    EXPECT_EQ(dmabufImportsFor(copied).count, 0);
    void* address = ::mmap(nullptr, 4096, PROT_READ, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
    const auto unexported =
        std::make_shared<V4l2Buffer>(MappedRegion(address, 4096), UniqueFd(), V4L2_PIX_FMT_YUYV, 16, 256);
    EXPECT_FALSE(unexported->exported());
    EXPECT_EQ(dmabufImportsFor(lentImage(unexported, YCbCrLayout::Yuyv, 128, 16, 256)).count, 0);
}

TEST(DmabufImport, TheDecisionNamesWhatIsMissing)
{
    EXPECT_EQ(dmabufImportUnavailableReason(true, true, true), "");
    EXPECT_NE(dmabufImportUnavailableReason(false, true, true).find("EGL_EXT_image_dma_buf_import"), std::string::npos);
    EXPECT_NE(dmabufImportUnavailableReason(true, false, true).find("EGL_KHR_image_base"), std::string::npos);
    EXPECT_NE(dmabufImportUnavailableReason(true, true, false).find("GL_OES_EGL_image"), std::string::npos);
    // kms_swrast cannot map another device's dmabuf (Mesa would crash on the first draw), but
    // can read its own device's buffers; other drivers take both.
    EXPECT_NE(dmabufImportUnavailableReason(true, true, true, "kms_swrast").find("kms_swrast"), std::string::npos);
    EXPECT_EQ(dmabufImportUnavailableReason(true, true, true, "kms_swrast", DmabufOrigin::RenderDevice), "");
    EXPECT_EQ(dmabufImportUnavailableReason(true, true, true, "iris"), "");
    EXPECT_EQ(dmabufImportUnavailableReason(true, true, true, "v3d", DmabufOrigin::OtherDevice), "");
}

// This display's answer, and what a lent buffer gets from the importer.
TEST(DmabufImport, FallsBackWhereTheDisplayCannotImport)
{
    std::shared_ptr<EglDisplay> display;
    std::unique_ptr<EglContext> context;
    try {
        display = EglDisplay::surfaceless();
        context = std::make_unique<EglContext>(display);
        context->makeCurrent();
    } catch (const RuntimeError& e) {
        GTEST_SKIP() << "no GLES 3 context: " << e.what();
    }
    DmabufImporter importer(*display);
    const bool extension = display->hasExtension("EGL_EXT_image_dma_buf_import");
    if (!extension) {
        EXPECT_FALSE(importer.usable());
        EXPECT_NE(importer.unavailableReason().find("EGL_EXT_image_dma_buf_import"), std::string::npos);
    }
    const int width = 64, height = 32;
    const auto buffer = memfdBuffer(std::vector<uint8_t>(size_t(width) * height * 3 / 2, 128), V4L2_PIX_FMT_NV12,
                                    height, size_t(width));
    const YCbCrImage image = lentImage(buffer, YCbCrLayout::Nv12, width, height, size_t(width));
    const DmabufTextures* textures = importer.texturesFor(image);
    if (!extension || !importer.usable()) {
        // No extension, or a memfd the driver would not take as a dmabuf: the upload draws.
        EXPECT_EQ(textures, nullptr);
        EXPECT_FALSE(importer.usable());
        EXPECT_EQ(importer.importedBuffers(), 0u);
        if (extension) {
            EXPECT_NE(importer.unavailableReason().find("importing a camera buffer failed"), std::string::npos);
        }
    } else {
        // A driver that imports memfds (newer llvmpipe): one import, reused for the same buffer.
        ASSERT_NE(textures, nullptr);
        EXPECT_NE(textures->luma, 0u);
        EXPECT_NE(textures->chroma, 0u);
        EXPECT_EQ(importer.texturesFor(image), textures);
        EXPECT_EQ(importer.importedBuffers(), 1u);
    }
    // The importer never keeps a buffer alive: only the frame's reference and ours remain.
    EXPECT_EQ(buffer.use_count(), 1 + 1);
}

} // namespace
} // namespace lumar
