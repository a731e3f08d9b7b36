#include "gles_renderer/display/gbm_surface.h"

#include <cerrno>
#include <cstring>
#include <string>
#include <utility>

#include <drm_fourcc.h>
#include <xf86drmMode.h>

#include "core/error.h"

namespace lumar {
namespace {

// What GBM keeps in a buffer object's user data: the framebuffer added for it, removed by
// GBM's destroy callback when the buffer object goes.
struct BufferFramebuffer {
    int drmFd = -1;
    uint32_t id = 0;
};

void destroyBufferFramebuffer(gbm_bo* /*bo*/, void* data)
{
    auto* framebuffer = static_cast<BufferFramebuffer*>(data);
    if (framebuffer->id)
        drmModeRmFB(framebuffer->drmFd, framebuffer->id);
    delete framebuffer;
}

} // namespace

GbmDevice::GbmDevice(int drmFd) : device_(gbm_create_device(drmFd))
{
    if (!device_)
        throw RuntimeError("cannot create a GBM device on the DRM node");
}

GbmDevice::GbmDevice(GbmDevice&& other) noexcept : device_(std::exchange(other.device_, nullptr)) {}

GbmDevice& GbmDevice::operator=(GbmDevice&& other) noexcept
{
    if (this != &other) {
        if (device_)
            gbm_device_destroy(device_);
        device_ = std::exchange(other.device_, nullptr);
    }
    return *this;
}

GbmDevice::~GbmDevice()
{
    if (device_)
        gbm_device_destroy(device_);
}

GbmSurface::GbmSurface(const GbmDevice& device, int width, int height, uint32_t format)
    : surface_(gbm_surface_create(device.handle(), uint32_t(width), uint32_t(height), format,
                                  GBM_BO_USE_SCANOUT | GBM_BO_USE_RENDERING))
{
    if (!surface_)
        throw RuntimeError("cannot create a " + std::to_string(width) + "x" + std::to_string(height) +
                           " GBM scan-out surface: " + std::strerror(errno));
}

GbmSurface::GbmSurface(GbmSurface&& other) noexcept : surface_(std::exchange(other.surface_, nullptr)) {}

GbmSurface& GbmSurface::operator=(GbmSurface&& other) noexcept
{
    if (this != &other) {
        if (surface_)
            gbm_surface_destroy(surface_);
        surface_ = std::exchange(other.surface_, nullptr);
    }
    return *this;
}

GbmSurface::~GbmSurface()
{
    if (surface_)
        gbm_surface_destroy(surface_);
}

LockedBuffer::LockedBuffer(const GbmSurface& surface)
    : surface_(surface.handle()), bo_(gbm_surface_lock_front_buffer(surface.handle()))
{
    if (!bo_)
        throw RuntimeError("GBM has no front buffer to lock (was eglSwapBuffers called?)");
}

LockedBuffer::LockedBuffer(LockedBuffer&& other) noexcept
    : surface_(std::exchange(other.surface_, nullptr)), bo_(std::exchange(other.bo_, nullptr))
{
}

LockedBuffer& LockedBuffer::operator=(LockedBuffer&& other) noexcept
{
    if (this != &other) {
        release();
        surface_ = std::exchange(other.surface_, nullptr);
        bo_ = std::exchange(other.bo_, nullptr);
    }
    return *this;
}

LockedBuffer::~LockedBuffer()
{
    release();
}

void LockedBuffer::release()
{
    if (bo_)
        gbm_surface_release_buffer(surface_, bo_);
    bo_ = nullptr;
    surface_ = nullptr;
}

uint32_t LockedBuffer::framebuffer(int drmFd, bool modifiers) const
{
    if (auto* existing = static_cast<BufferFramebuffer*>(gbm_bo_get_user_data(bo_)))
        return existing->id;

    const uint32_t width = gbm_bo_get_width(bo_);
    const uint32_t height = gbm_bo_get_height(bo_);
    const uint32_t format = gbm_bo_get_format(bo_);
    uint32_t handles[4] = {}, pitches[4] = {}, offsets[4] = {};
    uint64_t bufferModifiers[4] = {};
    const int planes = gbm_bo_get_plane_count(bo_);
    for (int i = 0; i < planes && i < 4; ++i) {
        handles[i] = gbm_bo_get_handle_for_plane(bo_, i).u32;
        pitches[i] = gbm_bo_get_stride_for_plane(bo_, i);
        offsets[i] = gbm_bo_get_offset(bo_, i);
        bufferModifiers[i] = gbm_bo_get_modifier(bo_);
    }
    // A buffer with no (or an invalid) modifier goes in without one: some drivers (bochs)
    // reject DRM_FORMAT_MOD_INVALID at mode-set.
    const bool withModifiers = modifiers && bufferModifiers[0] != DRM_FORMAT_MOD_INVALID;
    uint32_t id = 0;
    const int result = withModifiers ? drmModeAddFB2WithModifiers(drmFd, width, height, format, handles, pitches,
                                                                  offsets, bufferModifiers, &id, DRM_MODE_FB_MODIFIERS)
                                     : drmModeAddFB2(drmFd, width, height, format, handles, pitches, offsets, &id, 0);
    if (result != 0)
        throw RuntimeError(std::string("cannot add a DRM framebuffer for a GBM buffer: ") + std::strerror(-result));
    gbm_bo_set_user_data(bo_, new BufferFramebuffer{drmFd, id}, destroyBufferFramebuffer);
    return id;
}

} // namespace lumar
