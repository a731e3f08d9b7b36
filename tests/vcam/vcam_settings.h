// The virtual camera's settings, read from the environment each time the device is opened,
// so one test process can open it with different colorimetry and faults in turn.
//
//   LUMAR_VCAM_DEVICE            path served (default /dev/video0; need not exist)
//   LUMAR_VCAM_FORMATS           fourccs offered, in order (default YUYV,NV12,MJPG,GREY)
//   LUMAR_VCAM_YCBCR_ENC         601 (default) or 709
//   LUMAR_VCAM_QUANTIZATION      limited (default) or full
//   LUMAR_VCAM_FAULT_UNPLUG_AT=k      from frame k on, every ioctl fails ENODEV, poll POLLERR
//   LUMAR_VCAM_FAULT_STALL_AT=k, LUMAR_VCAM_FAULT_STALL_MS=t   frame k (and all later) come t ms late
//   LUMAR_VCAM_FAULT_DROP_EVERY=n     frames n-1, 2n-1, ... are never delivered (sequence gaps)
//   LUMAR_VCAM_FAULT_SHORT_EVERY=n    frames n-1, 2n-1, ... are delivered with half their bytes
//   LUMAR_VCAM_FAULT_CORRUPT_EVERY=n  MJPEG frames n-1, 2n-1, ...: the JPEG is cut after a third of
//                                     its bytes and the cut-off rest garbled (a bad USB transfer)
//   LUMAR_VCAM_JPEG_QUALITY=q         MJPEG quality, 1..100 (default 95), 4:2:2 as UVC cameras send
//   LUMAR_VCAM_SOURCE_CHANGE_AT=k     at frame k the input's resolution changes: frames stop, a
//                                     V4L2_EVENT_SOURCE_CHANGE is raised, and from then on only
//   LUMAR_VCAM_SOURCE_CHANGE_SIZE=WxH this size is offered (default 1280x720; even, 16..4096)
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
    int64_t corruptEvery = 0;
    // LUMAR_VCAM_PACED=1: the device keeps pace with its reader instead of the wall clock:
    // a frame falls due no sooner than its time, than one period after the frame before it,
    // and than the reader has taken that frame and queued a buffer for it; its sequence
    // number and timestamp stay those of the nominal timeline. The V4L2 source's tests use
    // it: on a loaded machine a reader descheduled for longer than the buffers last would
    // otherwise see drops, bursts of stale frames and early faults that no test injected.
    bool paced = false;
    int64_t jpegQuality = 95;
    int64_t sourceChangeAt = -1;
    uint32_t sourceChangeWidth = 1280;
    uint32_t sourceChangeHeight = 720;
};

// Unparseable values (and unknown fourccs) are ignored (the default is kept): a test library must not abort its host.
Settings settingsFromEnvironment();

} // namespace lumar::vcam
