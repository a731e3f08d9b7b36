#include "gles_renderer/display/drm_device.h"

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <system_error>

#include <fcntl.h>

#include "core/error.h"
#include "core/log.h"

namespace lumar {

std::string drmDriverName(int fd)
{
    const std::unique_ptr<drmVersion, DrmFree<drmVersion, drmFreeVersion>> version(drmGetVersion(fd));
    if (!version)
        return {};
    return {version->name, size_t(version->name_len)};
}

namespace {

bool hasConnectedConnector(const DrmDevice& device)
{
    const DrmResources resources = device.resources();
    for (int i = 0; resources && i < resources->count_connectors; ++i) {
        const DrmConnector connector = device.connector(resources->connectors[i]);
        if (connector && connector->connection == DRM_MODE_CONNECTED && connector->count_modes > 0)
            return true;
    }
    return false;
}

} // namespace

std::string connectorName(const drmModeConnector& connector)
{
    const char* type = drmModeGetConnectorTypeName(connector.connector_type);
    return std::string(type ? type : "Unknown") + "-" + std::to_string(connector.connector_type_id);
}

std::string drmFormatName(uint32_t fourcc)
{
    std::string name(4, ' ');
    for (int i = 0; i < 4; ++i)
        name[size_t(i)] = char((fourcc >> (8 * i)) & 0xff);
    return name;
}

std::vector<std::filesystem::path> drmCardNodes()
{
    std::vector<std::filesystem::path> nodes;
    std::error_code ec;
    for (const auto& entry : std::filesystem::directory_iterator("/dev/dri", ec))
        if (entry.path().filename().string().starts_with("card"))
            nodes.push_back(entry.path());
    std::sort(nodes.begin(), nodes.end());
    return nodes;
}

DrmDevice::DrmDevice(const std::filesystem::path& path) : path_(path)
{
    fd_.reset(::open(path.c_str(), O_RDWR | O_CLOEXEC));
    if (!fd_.valid())
        throw RuntimeError(path.string() + ": cannot open: " + std::strerror(errno));
    driver_ = drmDriverName(fd_.get());
    // Universal planes expose the primary plane as a plane (needed for atomic and for the
    // plane choice); atomic is optional, the legacy API is the fallback.
    if (drmSetClientCap(fd_.get(), DRM_CLIENT_CAP_UNIVERSAL_PLANES, 1) != 0)
        throw RuntimeError(path.string() + ": the driver '" + driver_ + "' lacks universal planes");
    atomic_ = drmSetClientCap(fd_.get(), DRM_CLIENT_CAP_ATOMIC, 1) == 0;
    if (!resources())
        throw RuntimeError(path.string() + ": no KMS resources (a render-only device?)");
}

std::optional<DrmDevice> DrmDevice::openPreferred(std::span<const std::string> drivers, std::string& why)
{
    std::vector<DrmDevice> candidates;
    why.clear();
    for (const auto& node : drmCardNodes()) {
        try {
            DrmDevice device(node);
            if (!hasConnectedConnector(device)) {
                why += node.string() + " (" + device.driver() + "): nothing connected; ";
                continue;
            }
            candidates.push_back(std::move(device));
        } catch (const RuntimeError& e) {
            why += std::string(e.what()) + "; ";
        }
    }
    if (candidates.empty() && why.empty())
        why = "no /dev/dri/card* node";
    if (drivers.empty())
        return candidates.empty() ? std::nullopt : std::optional<DrmDevice>(std::move(candidates.front()));
    for (const std::string& wanted : drivers)
        for (DrmDevice& device : candidates)
            if (device.driver() == wanted)
                return std::move(device);
    for (const DrmDevice& device : candidates)
        why += device.path().string() + " is driven by '" + device.driver() + "', which the board does not name; ";
    return std::nullopt;
}

DrmResources DrmDevice::resources() const
{
    return DrmResources(drmModeGetResources(fd_.get()));
}

DrmConnector DrmDevice::connector(uint32_t id) const
{
    return DrmConnector(drmModeGetConnector(fd_.get(), id));
}

std::vector<DrmPlaneInfo> DrmDevice::planes() const
{
    std::vector<DrmPlaneInfo> result;
    const DrmPlaneResources planeResources(drmModeGetPlaneResources(fd_.get()));
    for (uint32_t i = 0; planeResources && i < planeResources->count_planes; ++i) {
        const DrmPlane plane(drmModeGetPlane(fd_.get(), planeResources->planes[i]));
        if (!plane)
            continue;
        DrmPlaneInfo info;
        info.id = plane->plane_id;
        info.possibleCrtcs = plane->possible_crtcs;
        info.formats.assign(plane->formats, plane->formats + plane->count_formats);
        const auto type = propertyValue(plane->plane_id, DRM_MODE_OBJECT_PLANE, "type");
        info.type = !type                             ? "overlay"
                    : *type == DRM_PLANE_TYPE_PRIMARY ? "primary"
                    : *type == DRM_PLANE_TYPE_CURSOR  ? "cursor"
                                                      : "overlay";
        result.push_back(std::move(info));
    }
    return result;
}

uint32_t DrmDevice::propertyId(uint32_t objectId, uint32_t objectType, std::string_view name) const
{
    const DrmObjectProperties properties(drmModeObjectGetProperties(fd_.get(), objectId, objectType));
    for (uint32_t i = 0; properties && i < properties->count_props; ++i) {
        const DrmProperty property(drmModeGetProperty(fd_.get(), properties->props[i]));
        if (property && name == property->name)
            return property->prop_id;
    }
    return 0;
}

std::optional<uint64_t> DrmDevice::propertyValue(uint32_t objectId, uint32_t objectType, std::string_view name) const
{
    const DrmObjectProperties properties(drmModeObjectGetProperties(fd_.get(), objectId, objectType));
    for (uint32_t i = 0; properties && i < properties->count_props; ++i) {
        const DrmProperty property(drmModeGetProperty(fd_.get(), properties->props[i]));
        if (property && name == property->name)
            return properties->prop_values[i];
    }
    return std::nullopt;
}

} // namespace lumar
