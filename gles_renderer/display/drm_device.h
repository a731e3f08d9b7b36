// A DRM/KMS device node and RAII owners for the libdrm objects read from it (DESIGN.md §7).
// Every drmMode* structure libdrm hands out is held by a unique_ptr with its matching free
// function, so no error path can leak one.
#pragma once

#include <cstdint>
#include <filesystem>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include <xf86drm.h>
#include <xf86drmMode.h>

#include "core/unique_fd.h"

namespace lumar {

template <typename T, void (*Free)(T*)> struct DrmFree {
    void operator()(T* object) const
    {
        if (object)
            Free(object);
    }
};
using DrmResources = std::unique_ptr<drmModeRes, DrmFree<drmModeRes, drmModeFreeResources>>;
using DrmConnector = std::unique_ptr<drmModeConnector, DrmFree<drmModeConnector, drmModeFreeConnector>>;
using DrmEncoder = std::unique_ptr<drmModeEncoder, DrmFree<drmModeEncoder, drmModeFreeEncoder>>;
using DrmCrtc = std::unique_ptr<drmModeCrtc, DrmFree<drmModeCrtc, drmModeFreeCrtc>>;
using DrmPlaneResources = std::unique_ptr<drmModePlaneRes, DrmFree<drmModePlaneRes, drmModeFreePlaneResources>>;
using DrmPlane = std::unique_ptr<drmModePlane, DrmFree<drmModePlane, drmModeFreePlane>>;
using DrmObjectProperties =
    std::unique_ptr<drmModeObjectProperties, DrmFree<drmModeObjectProperties, drmModeFreeObjectProperties>>;
using DrmProperty = std::unique_ptr<drmModePropertyRes, DrmFree<drmModePropertyRes, drmModeFreeProperty>>;
using DrmAtomicRequest = std::unique_ptr<drmModeAtomicReq, DrmFree<drmModeAtomicReq, drmModeAtomicFree>>;

// The kernel's name for a connector: "HDMI-A-1", "Virtual-1".
std::string connectorName(const drmModeConnector& connector);

// One plane as the probe and the plane choice see it.
struct DrmPlaneInfo {
    uint32_t id = 0;
    uint32_t possibleCrtcs = 0; // bit i: the CRTC at index i of the resources
    std::string type;           // "primary" | "overlay" | "cursor"
    std::vector<uint32_t> formats;
};

// An open KMS-capable device node with universal planes enabled and atomic modesetting
// enabled when the driver offers it.
class DrmDevice {
public:
    // Opens `path`. Throws RuntimeError naming the node when it cannot be opened or has no
    // KMS resources (a render-only node).
    explicit DrmDevice(const std::filesystem::path& path);

    // The first card node (/dev/dri/card*) whose driver is the earliest of `drivers` (any
    // driver when empty) and that has a connected connector. nullopt when there is none;
    // `why` then says what was found, for the log.
    static std::optional<DrmDevice> openPreferred(std::span<const std::string> drivers, std::string& why);

    [[nodiscard]] int fd() const { return fd_.get(); }
    [[nodiscard]] const std::filesystem::path& path() const { return path_; }
    [[nodiscard]] const std::string& driver() const { return driver_; }
    [[nodiscard]] bool atomic() const { return atomic_; }
    // Disables atomic modesetting for the rest of this device's life (the legacy fallback).
    void useLegacyApi() { atomic_ = false; }

    [[nodiscard]] DrmResources resources() const;
    [[nodiscard]] DrmConnector connector(uint32_t id) const;
    [[nodiscard]] std::vector<DrmPlaneInfo> planes() const;
    // The id of property `name` of a KMS object, 0 when it has none.
    [[nodiscard]] uint32_t propertyId(uint32_t objectId, uint32_t objectType, std::string_view name) const;
    // The current value of property `name`, nullopt when the object has none.
    [[nodiscard]] std::optional<uint64_t> propertyValue(uint32_t objectId, uint32_t objectType,
                                                        std::string_view name) const;

private:
    std::filesystem::path path_;
    UniqueFd fd_;
    std::string driver_;
    bool atomic_ = false;
};

// The card nodes under /dev/dri, sorted.
std::vector<std::filesystem::path> drmCardNodes();

// "XR24" for DRM_FORMAT_XRGB8888.
std::string drmFormatName(uint32_t fourcc);

// The driver's name as drmGetVersion reports it on DRM fd `fd` ("bochs-drm", "vc4", "vgem"),
// empty on failure.
std::string drmDriverName(int fd);

} // namespace lumar
