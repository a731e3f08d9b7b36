#include "gles_renderer/display/drm_probe.h"

#include <algorithm>
#include <cstdio>

#include "core/error.h"
#include "gles_renderer/display/drm_device.h"

namespace lumar {
namespace {

std::string modeText(const drmModeModeInfo& mode)
{
    char text[64];
    std::snprintf(text, sizeof text, "%dx%d@%u%s", mode.hdisplay, mode.vdisplay, mode.vrefresh,
                  (mode.type & DRM_MODE_TYPE_PREFERRED) ? "*" : "");
    return text;
}

void describeDevice(const DrmDevice& device, std::vector<std::string>& lines)
{
    const DrmResources resources = device.resources();
    lines.push_back("  " + device.path().string() + ": driver " + device.driver() + ", " +
                    (device.atomic() ? "atomic" : "legacy only") + ", " + std::to_string(resources->count_crtcs) +
                    " CRTC(s)");
    for (int i = 0; i < resources->count_connectors; ++i) {
        const DrmConnector connector = device.connector(resources->connectors[i]);
        if (!connector)
            continue;
        std::string line = "    connector " + connectorName(*connector) + ": " +
                           (connector->connection == DRM_MODE_CONNECTED ? "connected" : "disconnected");
        const int shown = std::min(connector->count_modes, 6);
        for (int m = 0; m < shown; ++m)
            line += (m == 0 ? ", modes " : " ") + modeText(connector->modes[m]);
        if (connector->count_modes > shown)
            line += " (+" + std::to_string(connector->count_modes - shown) + ")";
        lines.push_back(line);
    }
    for (const DrmPlaneInfo& plane : device.planes()) {
        std::string line = "    plane " + std::to_string(plane.id) + ": " + plane.type + ", formats";
        for (const uint32_t format : plane.formats)
            line += " " + drmFormatName(format);
        lines.push_back(line);
    }
}

} // namespace

std::vector<std::string> describeDrmDevices()
{
    std::vector<std::string> lines;
    const auto nodes = drmCardNodes();
    if (nodes.empty())
        lines.emplace_back("  none (no /dev/dri/card*): output is headless only");
    for (const auto& node : nodes) {
        try {
            describeDevice(DrmDevice(node), lines);
        } catch (const RuntimeError& e) {
            lines.push_back("  " + std::string(e.what()));
        }
    }
    return lines;
}

} // namespace lumar
