#include "gles_renderer/gl/dmabuf_image.h"

#include <algorithm>
#include <sstream>

#include <drm_fourcc.h>

#include "core/log.h"
#include "gles_renderer/gl/egl_context.h"
#include "gles_renderer/gl/gl_check.h"

namespace lumar {
namespace {

std::string eglErrorText(EGLint error)
{
    std::ostringstream text;
    text << "EGL error 0x" << std::hex << error;
    return text.str();
}

} // namespace

DmabufImports dmabufImportsFor(const YCbCrImage& image)
{
    DmabufImports imports;
    const CameraBuffer* buffer = image.buffer.get();
    if (buffer == nullptr || !buffer->exported() || image.width <= 0 || image.height <= 0)
        return imports;
    const auto& planes = buffer->planes();
    if (image.layout == YCbCrLayout::Nv12 && buffer->drmFourcc() == DRM_FORMAT_NV12 && planes[1].dmabufFd >= 0) {
        imports.planes[0] = {DRM_FORMAT_R8,      image.width,      image.height,
                             planes[0].dmabufFd, planes[0].offset, uint32_t(image.stride0)};
        // GR88 is little-endian R then G: R = Cb, G = Cr, as the uploaded RG8 plane.
        imports.planes[1] = {DRM_FORMAT_GR88,    image.width / 2,  image.height / 2,
                             planes[1].dmabufFd, planes[1].offset, uint32_t(image.stride1)};
        imports.count = 2;
    } else if (image.layout == YCbCrLayout::Yuyv && buffer->drmFourcc() == DRM_FORMAT_YUYV) {
        // ABGR8888 is little-endian R G B A: Y0 Cb Y1 Cr, as the uploaded RGBA8 rows.
        imports.planes[0] = {DRM_FORMAT_ABGR8888, image.width / 2,  image.height,
                             planes[0].dmabufFd,  planes[0].offset, uint32_t(image.stride0)};
        imports.count = 1;
    }
    return imports;
}

std::vector<EGLint> dmabufImageAttributes(const DmabufPlaneImport& plane, bool linearModifier)
{
    std::vector<EGLint> attributes{EGL_WIDTH,
                                   plane.width,
                                   EGL_HEIGHT,
                                   plane.height,
                                   EGL_LINUX_DRM_FOURCC_EXT,
                                   EGLint(plane.drmFormat),
                                   EGL_DMA_BUF_PLANE0_FD_EXT,
                                   plane.fd,
                                   EGL_DMA_BUF_PLANE0_OFFSET_EXT,
                                   EGLint(plane.offset),
                                   EGL_DMA_BUF_PLANE0_PITCH_EXT,
                                   EGLint(plane.pitch)};
    if (linearModifier) {
        attributes.insert(attributes.end(),
                          {EGL_DMA_BUF_PLANE0_MODIFIER_LO_EXT, EGLint(DRM_FORMAT_MOD_LINEAR & 0xffffffffu),
                           EGL_DMA_BUF_PLANE0_MODIFIER_HI_EXT, EGLint(DRM_FORMAT_MOD_LINEAR >> 32)});
    }
    attributes.push_back(EGL_NONE);
    return attributes;
}

std::string dmabufImportUnavailableReason(bool eglDmaBufImport, bool eglImageBase, bool glEglImage,
                                          std::string_view driverName, DmabufOrigin origin)
{
    if (!eglDmaBufImport)
        return "the EGL display has no EGL_EXT_image_dma_buf_import";
    if (!eglImageBase)
        return "the EGL display has no EGL_KHR_image_base";
    if (!glEglImage)
        return "the GLES context has no GL_OES_EGL_image";
    if (driverName == "kms_swrast" && origin == DmabufOrigin::OtherDevice)
        return "the EGL driver is kms_swrast, which cannot map another device's dmabuf (the kernel refuses "
               "DRM_IOCTL_MODE_MAP_DUMB for imported buffers)";
    return {};
}

std::string dmabufImportUnavailableReason(const EglDisplay& display, DmabufOrigin origin)
{
    return dmabufImportUnavailableReason(display.hasExtension("EGL_EXT_image_dma_buf_import"),
                                         display.hasExtension("EGL_KHR_image_base"), hasGlExtension("GL_OES_EGL_image"),
                                         display.driverName(), origin);
}

EglImage::EglImage(EglImage&& other) noexcept
    : display_(std::exchange(other.display_, EGL_NO_DISPLAY)), image_(std::exchange(other.image_, EGL_NO_IMAGE_KHR)),
      destroy_(std::exchange(other.destroy_, nullptr))
{
}

EglImage& EglImage::operator=(EglImage&& other) noexcept
{
    if (this != &other) {
        reset();
        display_ = std::exchange(other.display_, EGL_NO_DISPLAY);
        image_ = std::exchange(other.image_, EGL_NO_IMAGE_KHR);
        destroy_ = std::exchange(other.destroy_, nullptr);
    }
    return *this;
}

void EglImage::reset()
{
    if (image_ != EGL_NO_IMAGE_KHR && destroy_ != nullptr)
        destroy_(display_, image_);
    image_ = EGL_NO_IMAGE_KHR;
}

GlFence& GlFence::operator=(GlFence&& other) noexcept
{
    if (this != &other) {
        reset();
        sync_ = std::exchange(other.sync_, nullptr);
    }
    return *this;
}

GlFence GlFence::insert()
{
    GlFence fence;
    fence.sync_ = glFenceSync(GL_SYNC_GPU_COMMANDS_COMPLETE, 0);
    return fence;
}

bool GlFence::wait(uint64_t timeoutNs) const
{
    if (sync_ == nullptr)
        return true;
    const GLenum result = glClientWaitSync(sync_, GL_SYNC_FLUSH_COMMANDS_BIT, timeoutNs);
    return result == GL_ALREADY_SIGNALED || result == GL_CONDITION_SATISFIED;
}

void GlFence::reset()
{
    if (sync_ != nullptr)
        glDeleteSync(sync_);
    sync_ = nullptr;
}

DmabufImporter::DmabufImporter(const EglDisplay& display, DmabufOrigin origin) : display_(display.handle())
{
    reason_ = dmabufImportUnavailableReason(display, origin);
    if (reason_.empty()) {
        createImage_ = reinterpret_cast<PFNEGLCREATEIMAGEKHRPROC>(eglGetProcAddress("eglCreateImageKHR"));
        destroyImage_ = reinterpret_cast<PFNEGLDESTROYIMAGEKHRPROC>(eglGetProcAddress("eglDestroyImageKHR"));
        imageTargetTexture_ = reinterpret_cast<ImageTargetTexture>(eglGetProcAddress("glEGLImageTargetTexture2DOES"));
        if (!createImage_ || !destroyImage_ || !imageTargetTexture_)
            reason_ = "the EGL image entry points are missing";
    }
    linearModifier_ = display.hasExtension("EGL_EXT_image_dma_buf_import_modifiers");
}

void DmabufImporter::dropStaleEntries()
{
    // Its stream stopped and no frame shows it: the images would only pin the memory.
    std::erase_if(entries_, [](const Entry& entry) { return entry.buffer.expired(); });
}

std::string DmabufImporter::import(const YCbCrImage& image, Entry& entry) const
{
    const DmabufImports imports = dmabufImportsFor(image);
    for (int i = 0; i < imports.count; ++i) {
        const DmabufPlaneImport& plane = imports.planes[size_t(i)];
        const std::vector<EGLint> attributes = dmabufImageAttributes(plane, linearModifier_);
        const EGLImageKHR handle =
            createImage_(display_, EGL_NO_CONTEXT, EGL_LINUX_DMA_BUF_EXT, nullptr, attributes.data());
        if (handle == EGL_NO_IMAGE_KHR)
            return "eglCreateImageKHR of a " + std::to_string(plane.width) + "x" + std::to_string(plane.height) +
                   " plane (pitch " + std::to_string(plane.pitch) + ", offset " + std::to_string(plane.offset) +
                   ") failed: " + eglErrorText(eglGetError());
        entry.images[size_t(i)] = EglImage(display_, handle, destroyImage_);
        entry.textures[size_t(i)] = GlTexture::create();
        glBindTexture(GL_TEXTURE_2D, entry.textures[size_t(i)].name());
        imageTargetTexture_(GL_TEXTURE_2D, handle);
        // The shader reads texels with texelFetch only.
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
        if (const GLenum error = glGetError(); error != GL_NO_ERROR)
            return "glEGLImageTargetTexture2DOES failed: GL error " + std::to_string(error);
    }
    glBindTexture(GL_TEXTURE_2D, 0);
    entry.bound = imports.count == 2 ? DmabufTextures{entry.textures[0].name(), entry.textures[1].name()}
                                     : DmabufTextures{0, entry.textures[0].name()};
    return {};
}

const DmabufTextures* DmabufImporter::texturesFor(const YCbCrImage& image)
{
    dropStaleEntries();
    if (!image.buffer)
        return nullptr; // copied planes: uploaded
    if (!usable()) {
        // Said once, when the first frame that could have been imported arrives.
        if (!loggedUnavailable_ && dmabufImportsFor(image).count > 0)
            LUMAR_LOG(Render, Info) << "camera buffers: no dmabuf import (" << reason_
                                    << "); uploaded with glTexSubImage2D";
        loggedUnavailable_ = loggedUnavailable_ || dmabufImportsFor(image).count > 0;
        return nullptr;
    }
    const uint64_t id = image.buffer->id();
    const auto found = std::find_if(entries_.begin(), entries_.end(), [&](const Entry& e) { return e.id == id; });
    if (found != entries_.end())
        return &found->bound;
    if (dmabufImportsFor(image).count == 0)
        return nullptr; // not exported: the plain upload reads the mapping
    if (entries_.empty() && !loggedUnavailable_)
        LUMAR_LOG(Render, Info) << "camera buffers: imported as dmabufs (zero-copy)";
    Entry entry;
    entry.id = id;
    entry.buffer = image.buffer;
    if (const std::string problem = import(image, entry); !problem.empty()) {
        reason_ = "importing a camera buffer failed: " + problem;
        LUMAR_LOG(Render, Warn) << "camera buffers: " << reason_ << "; uploaded with glTexSubImage2D from now on";
        loggedUnavailable_ = true;
        entries_.clear();
        return nullptr;
    }
    entries_.push_back(std::move(entry));
    return &entries_.back().bound;
}

} // namespace lumar
