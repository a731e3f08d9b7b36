// Zero-copy camera frames: a lent camera buffer's dmabuf (core/ycbcr_image.h: CameraBuffer)
// imported as EGL images (EGL_EXT_image_dma_buf_import) and bound to textures the YCbCr
// background shader samples like uploaded planes. Each plane is its own single-plane image of
// an RGB-class format, NV12 as R8 (Y) + GR88 (Cb Cr at half size), YUYV as ABGR8888 of half the
// width (bytes Y0 Cb Y1 Cr in R G B A), instead of one NV12 image sampled through
// GL_TEXTURE_EXTERNAL_OES: the shader keeps texelFetch of exact code values and lumar's own
// matrix and range (the driver's, from the frame), where an external sampler would convert
// with whatever the GL driver does for the EGL_YUV_* hints; Mesa lowers external NV12 to the
// same two planes anyway, and R8/GR88 dmabuf imports work on every Gallium driver that can
// sample those formats.
// Each buffer is imported once, when first seen, and its images and textures are dropped when
// the buffer is gone (its stream stopped and no frame holds it). A display without the
// extension, a driver that cannot read another device's buffers (kms_swrast), or a failed
// import, is logged once and leaves the frame to the plain upload.
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include <EGL/egl.h>
#include <EGL/eglext.h>

#include "core/ycbcr_image.h"
#include "gles_renderer/gl/gl_object.h"

namespace lumar {

class EglDisplay;

// One plane of a camera buffer as a single-plane dmabuf image.
struct DmabufPlaneImport {
    uint32_t drmFormat = 0; // DRM_FORMAT_R8, _GR88 or _ABGR8888
    int width = 0;          // texels
    int height = 0;
    int fd = -1;
    uint32_t offset = 0; // bytes into the dmabuf
    uint32_t pitch = 0;  // bytes per row
};

struct DmabufImports {
    std::array<DmabufPlaneImport, 2> planes{};
    int count = 0; // 0: nothing to import (no exported buffer, or a layout lumar cannot import)
};

// The images `image` needs: NV12 two (luma, chroma), YUYV one (its packed rows).
DmabufImports dmabufImportsFor(const YCbCrImage& image);

// eglCreateImageKHR's attribute list for one plane, EGL_NONE-terminated. With `linearModifier`
// (the display has EGL_EXT_image_dma_buf_import_modifiers) the plane says it is linear, as
// V4L2 MMAP buffers are; without, the driver assumes so.
std::vector<EGLint> dmabufImageAttributes(const DmabufPlaneImport& plane, bool linearModifier);

// Whose dmabufs an importer is given. Zero-copy capture lends another device's (the camera's);
// the render device's own (its dumb buffers, exported) are what the import can be tested with
// where no camera shares memory with the GPU (tests/gl/dmabuf_device_test.cpp).
enum class DmabufOrigin { OtherDevice, RenderDevice };

// Why buffers of `origin` cannot be imported on a display and context with these extensions
// and this DRI driver (EglDisplay::driverName); empty when they can.
// kms_swrast (llvmpipe on a KMS or vgem node) reads an imported buffer through
// DRM_IOCTL_MODE_MAP_DUMB, which the kernel refuses for a buffer another device exported, and
// Mesa (22.3) then dereferences the failed mapping on the first draw: a camera's buffers
// would crash the daemon, so they are not imported there.
std::string dmabufImportUnavailableReason(bool eglDmaBufImport, bool eglImageBase, bool glEglImage,
                                          std::string_view driverName = {},
                                          DmabufOrigin origin = DmabufOrigin::OtherDevice);
// The same for `display` and the GLES context current now (its extensions, its driver).
std::string dmabufImportUnavailableReason(const EglDisplay& display, DmabufOrigin origin = DmabufOrigin::OtherDevice);

// An EGLImage, destroyed with its display's eglDestroyImageKHR. Move-only.
class EglImage {
public:
    EglImage() = default;
    EglImage(EGLDisplay display, EGLImageKHR image, PFNEGLDESTROYIMAGEKHRPROC destroy)
        : display_(display), image_(image), destroy_(destroy)
    {
    }
    EglImage(EglImage&& other) noexcept;
    EglImage& operator=(EglImage&& other) noexcept;
    EglImage(const EglImage&) = delete;
    EglImage& operator=(const EglImage&) = delete;
    ~EglImage() { reset(); }

    [[nodiscard]] EGLImageKHR handle() const { return image_; }
    void reset();

private:
    EGLDisplay display_ = EGL_NO_DISPLAY;
    EGLImageKHR image_ = EGL_NO_IMAGE_KHR;
    PFNEGLDESTROYIMAGEKHRPROC destroy_ = nullptr;
};

// A GL fence (glFenceSync), deleted with its owner. Move-only; the context must be current.
class GlFence {
public:
    GlFence() = default;
    GlFence(GlFence&& other) noexcept : sync_(std::exchange(other.sync_, nullptr)) {}
    GlFence& operator=(GlFence&& other) noexcept;
    GlFence(const GlFence&) = delete;
    GlFence& operator=(const GlFence&) = delete;
    ~GlFence() { reset(); }

    // A fence after the commands issued so far.
    static GlFence insert();
    // Waits (flushing) until the GPU has passed the fence, at most `timeoutNs`; true when it
    // has (or there is no fence).
    bool wait(uint64_t timeoutNs) const;
    void reset();

private:
    GLsync sync_ = nullptr;
};

// The textures of one imported camera buffer, bound like BackgroundPass's uploaded planes:
// NV12 luma (R8) and chroma (GR88); YUYV only `chroma` (its packed rows), luma unused (0).
struct DmabufTextures {
    GLuint luma = 0;
    GLuint chroma = 0;
};

class DmabufImporter {
public:
    // Decides, for `display` and the context current now, whether buffers of `origin` can be
    // imported (logs why not, once). The display must outlive the importer.
    explicit DmabufImporter(const EglDisplay& display, DmabufOrigin origin = DmabufOrigin::OtherDevice);
    DmabufImporter(const DmabufImporter&) = delete;
    DmabufImporter& operator=(const DmabufImporter&) = delete;

    [[nodiscard]] bool usable() const { return reason_.empty(); }
    [[nodiscard]] const std::string& unavailableReason() const { return reason_; }

    // The textures showing `image`'s lent buffer, imported the first time it is seen. nullptr
    // when the frame has no exported buffer, importing is unavailable, or the import fails
    // (logged once; importing is then off for this importer's life: the plain upload draws).
    // Drops the imports of buffers that no longer exist.
    const DmabufTextures* texturesFor(const YCbCrImage& image);

    [[nodiscard]] size_t importedBuffers() const { return entries_.size(); }

private:
    struct Entry {
        uint64_t id = 0;
        std::weak_ptr<const CameraBuffer> buffer;
        std::array<EglImage, 2> images;
        std::array<GlTexture, 2> textures;
        DmabufTextures bound;
    };
    // Imports one buffer; a reason why not when it fails.
    std::string import(const YCbCrImage& image, Entry& entry) const;
    void dropStaleEntries();

    EGLDisplay display_ = EGL_NO_DISPLAY;
    bool linearModifier_ = false;
    std::string reason_; // why importing is unavailable; empty: it is available
    bool loggedUnavailable_ = false;
    PFNEGLCREATEIMAGEKHRPROC createImage_ = nullptr;
    PFNEGLDESTROYIMAGEKHRPROC destroyImage_ = nullptr;
    // glEGLImageTargetTexture2DOES (GL_OES_EGL_image; declared here rather than through
    // gl2ext.h, which cannot follow gl3.h).
    using ImageTargetTexture = void(GL_APIENTRY*)(GLenum target, void* image);
    ImageTargetTexture imageTargetTexture_ = nullptr;
    std::vector<Entry> entries_;
};

} // namespace lumar
