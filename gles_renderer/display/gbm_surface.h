// GBM objects for KMS scan-out (DESIGN.md §7): the device on a DRM node, the surface EGL
// renders into, and its locked front buffers with the DRM framebuffer each one carries.
#pragma once

#include <cstdint>

#include <gbm.h>

namespace lumar {

class GbmDevice {
public:
    // Throws RuntimeError. `drmFd` must outlive the device.
    explicit GbmDevice(int drmFd);
    GbmDevice(GbmDevice&& other) noexcept;
    GbmDevice& operator=(GbmDevice&& other) noexcept;
    GbmDevice(const GbmDevice&) = delete;
    GbmDevice& operator=(const GbmDevice&) = delete;
    ~GbmDevice();

    [[nodiscard]] gbm_device* handle() const { return device_; }

private:
    gbm_device* device_ = nullptr;
};

class GbmSurface {
public:
    // A scan-out surface of `format` (DRM fourcc). Throws RuntimeError.
    GbmSurface(const GbmDevice& device, int width, int height, uint32_t format);
    GbmSurface(GbmSurface&& other) noexcept;
    GbmSurface& operator=(GbmSurface&& other) noexcept;
    GbmSurface(const GbmSurface&) = delete;
    GbmSurface& operator=(const GbmSurface&) = delete;
    ~GbmSurface();

    [[nodiscard]] gbm_surface* handle() const { return surface_; }

private:
    gbm_surface* surface_ = nullptr;
};

// A front buffer locked after eglSwapBuffers; released back to its surface when destroyed
// (after KMS stopped scanning it out).
class LockedBuffer {
public:
    LockedBuffer() = default;
    // Locks the surface's new front buffer. Throws RuntimeError when there is none.
    explicit LockedBuffer(const GbmSurface& surface);
    LockedBuffer(LockedBuffer&& other) noexcept;
    LockedBuffer& operator=(LockedBuffer&& other) noexcept;
    LockedBuffer(const LockedBuffer&) = delete;
    LockedBuffer& operator=(const LockedBuffer&) = delete;
    ~LockedBuffer();

    [[nodiscard]] bool valid() const { return bo_ != nullptr; }
    [[nodiscard]] gbm_bo* bo() const { return bo_; }
    // The DRM framebuffer of this buffer, added on first use and removed with the buffer
    // object (GBM reuses its buffers, so each is added once). `modifiers`: pass the buffer's
    // format modifier (false for drivers that reject them). Throws RuntimeError.
    [[nodiscard]] uint32_t framebuffer(int drmFd, bool modifiers) const;

private:
    void release();

    gbm_surface* surface_ = nullptr;
    gbm_bo* bo_ = nullptr;
};

} // namespace lumar
