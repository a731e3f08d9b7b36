// The config's [camera.controls] and frame rate as libcamera controls, the counterpart of the
// V4L2 backend's v4l2_controls: each setting is checked against what the camera advertises
// (Camera::controls()) first. A control the camera lacks is a warning and is skipped; a value
// outside the advertised range is clamped with a warning. Pure functions of the config and a
// ControlInfoMap, so they are tested without a camera.
//
//   exposure_us "auto"    AeEnable = true
//   exposure_us N         AeEnable = false, ExposureTime = N (microseconds, as in the config)
//   gain N                AnalogueGain = N / 100 (libcamera's gain is a multiplier: 100 = 1.0x)
//   white_balance_k auto  AwbEnable = true
//   white_balance_k K     AwbEnable = false, ColourTemperature = K; a camera without a
//                         settable ColourTemperature (Raspberry Pi) gets ColourGains of a
//                         black body at K seen by an sRGB sensor (approximate: real sensors
//                         differ, but the direction and rough size are right)
//   power_line_hz 0/50/60 AeFlickerMode off/manual + AeFlickerPeriod 10000/8333 us, looked up by
//                         name: libcamera has them from v0.2 (Debian 12's v0.0.3 has none, so
//                         there it is a warning)
#pragma once

#include <array>
#include <optional>
#include <string>
#include <vector>

#include <libcamera/controls.h>

#include "config/config.h"

namespace lumar {

struct AppliedLibcameraControl {
    std::string name;  // the config key and the libcamera control, for messages
    std::string value; // what was set (after clamping), as text
};

// Adds the controls `config` asks for to `controls` (a list on the camera's ControlInfoMap),
// automatic modes before the manual values they unlock. Warns (naming `camera`) for what the
// camera lacks; never throws. Returns what was set, in order.
std::vector<AppliedLibcameraControl> addLibcameraControls(const CameraControlsConfig& config,
                                                          const libcamera::ControlInfoMap& info,
                                                          libcamera::ControlList& controls, const std::string& camera);

// The FrameDurationLimits (minimum = maximum, microseconds) for `fps`, clamped into the range
// `info` advertises (an advertised range with a minimum above the request lowers the rate).
// nullopt when the camera has no FrameDurationLimits or fps <= 0.
std::optional<std::array<int64_t, 2>> frameDurationFor(double fps, const libcamera::ControlInfoMap& info);

// ColourGains (red, blue) that neutralise a black body at `kelvin` for an sRGB (Rec. 709
// primaries, D65 white) sensor: about (1, 1) at 6500 K, red < 1 and blue > 1 for warmer light.
// `kelvin` is clamped into [1667, 25000], the range of the Planckian locus fit used.
std::array<float, 2> colourGainsForTemperature(int kelvin);

} // namespace lumar
