// The setup view (issue 21, `[output] overlay = true`, `lumar run --overlay`): what the
// tracker found, drawn over the live picture so an integrator sees why an object is not where
// they expect — each detected tag's outline, id, reprojection error and axes, each map's axes
// and error, the region-of-interest windows searched, and a status line. Built here as plain
// lines and text (gles_renderer/overlay/overlay_scene.h) that the renderer draws after
// compositing, so the window, KMS and headless outputs all show it.
#pragma once

#include <functional>
#include <span>
#include <string>
#include <vector>

#include "core/camera_model.h"
#include "gles_renderer/overlay/overlay_scene.h"
#include "tracking/tag_map.h"
#include "tracking/tag_tracker.h"

namespace lumar {

struct SetupOverlayInput {
    CameraIntrinsics intrinsics;
    std::span<const TagDetection> detections;
    std::span<const MapDetection> maps;
    // A tag's side in metres (0: unknown, no axes drawn); a map's axes are as long as its
    // largest tag.
    std::function<double(int id)> tagSize;
    std::function<double(int mapIndex)> mapAxisLength;
    // The regions of interest the tracker searched for these detections (none: the whole
    // frame), each outlined on its border pixels, thin, in kOverlaySearchWindow.
    std::span<const SearchWindow> searchWindows;
    std::string status; // the status line, top left
};

// Colours of the setup view: outlines of tags with a pose green, without one (size unknown,
// pose failed) yellow; axes x red, y green, z blue, as most tools draw them.
inline constexpr OverlayColor kOverlayTagWithPose{40, 255, 80, 255};
inline constexpr OverlayColor kOverlayTagWithoutPose{255, 220, 0, 255};
inline constexpr OverlayColor kOverlayAxisX{255, 40, 40, 255};
inline constexpr OverlayColor kOverlayAxisY{40, 255, 40, 255};
inline constexpr OverlayColor kOverlayAxisZ{60, 120, 255, 255};
inline constexpr OverlayColor kOverlaySearchWindow{0, 220, 255, 200};

// Writes the view into `out` (cleared first, its buffers reused frame to frame). Line widths
// and text scale grow with the image: 2 px and scale 1 up to 1280 pixels wide.
void buildSetupOverlay(const SetupOverlayInput& input, OverlayScene& out);

} // namespace lumar
