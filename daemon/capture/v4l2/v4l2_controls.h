// The config's [camera.controls] (exposure, gain, white balance, power-line frequency) applied
// to an open V4L2 device. Every setting is checked against the device's own description of
// the control first (VIDIOC_QUERYCTRL/QUERYMENU): a control the device lacks is a warning and
// is skipped, a value outside its range is clamped (and snapped to its step) with a warning.
// All settings go in one VIDIOC_S_EXT_CTRLS, automatic modes before the manual values they
// unlock; a device that refuses it gets them one by one with VIDIOC_S_CTRL.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "config/config.h"

namespace lumar {

struct AppliedControl {
    uint32_t id = 0;
    std::string name; // the config key and the V4L2 control, for messages
    int32_t requested = 0;
    int32_t value = 0; // what was sent (after clamping)
    bool set = false;  // the device accepted it
};

// Never throws for a control problem (only warnings); returns what was attempted.
std::vector<AppliedControl> applyCameraControls(const std::string& device, int fd, const CameraControlsConfig& config);

} // namespace lumar
