// The KMS display a configuration asks for (`[output] sink = "kms"`, DESIGN.md §7): the board
// profile's [display] preferences with the [output] keys on top, opened once per process
// (a reload keeps the display and its mode).
#pragma once

#include <memory>

#include "config/config.h"
#include "gles_renderer/display/kms_display.h"

namespace lumar {

// The board's [display] choice (drivers, connector, plane, modifiers) under the [output]
// overrides (drm_device, connector, plane, mode).
KmsDisplayOptions kmsDisplayOptions(const Config& config);

// The display, or nullptr (with one warning naming what was found) when there is no usable
// DRM device: the caller falls back to the headless sink. Throws RuntimeError when a device
// exists but cannot be driven.
std::unique_ptr<KmsDisplay> openKmsDisplay(const Config& config);

} // namespace lumar
