#include "setup_overlay.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <optional>

#include "gles_renderer/overlay/bitmap_font.h"

namespace lumar {
namespace {

// A point of the camera frame in pixels; nullopt behind the camera (or too close to its
// plane for the projection to mean anything).
std::optional<glm::dvec2> projected(const CameraIntrinsics& k, const glm::dvec3& p)
{
    if (!(p.z > 1e-6) || !std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
        return std::nullopt;
    return k.project(p);
}

void addAxes(const CameraIntrinsics& k, const Pose& cameraFromFrame, double length, float width, OverlayScene& out)
{
    const std::optional<glm::dvec2> origin = projected(k, cameraFromFrame.t);
    if (!origin || !(length > 0.0))
        return;
    const glm::dvec3 axes[3] = {{length, 0, 0}, {0, length, 0}, {0, 0, length}};
    const OverlayColor colours[3] = {kOverlayAxisX, kOverlayAxisY, kOverlayAxisZ};
    for (int a = 0; a < 3; ++a)
        if (const std::optional<glm::dvec2> end = projected(k, cameraFromFrame.apply(axes[a])))
            out.lines.push_back({*origin, *end, colours[a], width});
}

std::string format(const char* pattern, auto... values)
{
    char text[160];
    std::snprintf(text, sizeof text, pattern, values...);
    return text;
}

} // namespace

void buildSetupOverlay(const SetupOverlayInput& input, OverlayScene& out)
{
    out.clear();
    const CameraIntrinsics& k = input.intrinsics;
    // Legible from a desk: 2 px lines and 14 px text at 1280 wide, thicker and larger above.
    const int scale = std::max(1, k.width / 1280 + (k.width % 1280 >= 640 ? 1 : 0));
    const float width = 2.0f * float(scale);
    const OverlayColor labelBackground{0, 0, 0, 170};

    for (const SearchWindow& w : input.searchWindows) {
        // The window's outer pixel edges, as a 1-px line along its border pixels' centres.
        const glm::dvec2 c[4] = {{w.x0, w.y0}, {w.x1 - 1, w.y0}, {w.x1 - 1, w.y1 - 1}, {w.x0, w.y1 - 1}};
        for (int i = 0; i < 4; ++i)
            out.lines.push_back({c[i], c[(i + 1) % 4], kOverlaySearchWindow, float(scale)});
    }

    for (const TagDetection& d : input.detections) {
        const OverlayColor outline = d.hasPose ? kOverlayTagWithPose : kOverlayTagWithoutPose;
        for (int i = 0; i < 4; ++i)
            out.lines.push_back({d.corners[size_t(i)], d.corners[size_t((i + 1) % 4)], outline, width});
        const double size = input.tagSize ? input.tagSize(d.id) : 0.0;
        if (d.hasPose)
            addAxes(k, d.cameraFromMarker, 0.5 * size, width, out);
        // The label under the tag's lowest corner, centred on the tag.
        double centreX = 0.0, bottom = d.corners[0].y;
        for (const glm::dvec2& c : d.corners) {
            centreX += 0.25 * c.x;
            bottom = std::max(bottom, c.y);
        }
        const std::string label =
            d.hasPose ? format("id %d  %.2f px", d.id, d.reprojectionErrorPx) : format("id %d  no pose", d.id);
        OverlayText text;
        text.text = label;
        text.scale = scale;
        text.color = outline;
        text.background = labelBackground;
        text.topLeft = {centreX - 0.5 * overlayFont().textWidth(label, scale), bottom + 4.0 * scale};
        out.texts.push_back(std::move(text));
    }

    for (const MapDetection& m : input.maps) {
        const double length = input.mapAxisLength ? input.mapAxisLength(m.index) : 0.0;
        addAxes(k, m.cameraFromMap, length, 1.5f * width, out);
        if (const std::optional<glm::dvec2> origin = projected(k, m.cameraFromMap.t)) {
            OverlayText text;
            text.text = format("map %s  %d tags  %.2f px", m.name.c_str(), m.tagsUsed, m.reprojectionErrorPx);
            text.scale = scale;
            text.background = labelBackground;
            text.topLeft = *origin + glm::dvec2(6.0 * scale, 6.0 * scale);
            out.texts.push_back(std::move(text));
        }
    }

    if (!input.status.empty()) {
        OverlayText status;
        status.text = input.status;
        status.scale = scale;
        status.background = labelBackground;
        status.padding = 3 * scale;
        status.topLeft = {6.0 * scale, 6.0 * scale};
        out.texts.push_back(std::move(status));
    }
}

} // namespace lumar
