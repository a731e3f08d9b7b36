// The virtual camera's settings, read from the environment each time the device is opened,
// so one test process can open it with different colorimetry and faults in turn.
//
//   LUMAR_VCAM_DEVICE            path served (default /dev/video0; need not exist)
//   LUMAR_VCAM_FORMATS           fourccs offered, in order (default YUYV,NV12,GREY)
//   LUMAR_VCAM_YCBCR_ENC         601 (default) or 709
//   LUMAR_VCAM_QUANTIZATION      limited (default) or full
//   LUMAR_VCAM_FAULT_UNPLUG_AT=k      from frame k on, every ioctl fails ENODEV, poll POLLERR
//   LUMAR_VCAM_FAULT_STALL_AT=k, LUMAR_VCAM_FAULT_STALL_MS=t   frame k (and all later) come t ms late
//   LUMAR_VCAM_FAULT_DROP_EVERY=n     frames n-1, 2n-1, ... are never delivered (sequence gaps)
//   LUMAR_VCAM_FAULT_SHORT_EVERY=n    frames n-1, 2n-1, ... are delivered with half their bytes
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace lumar::vcam {

struct Settings {
    std::string devicePath = "/dev/video0";
    std::vector<uint32_t> pixelFormats; // never empty after settingsFromEnvironment()
    bool bt709 = false;
    bool fullRange = false;
    int64_t unplugAt = -1; // -1: off
    int64_t stallAt = -1;
    int64_t stallMs = 0;
    int64_t dropEvery = 0; // 0: off
    int64_t shortEvery = 0;
};

// Unparseable values (and unknown fourccs) are ignored (the default is kept): a test library must not abort its host.
Settings settingsFromEnvironment();

} // namespace lumar::vcam
