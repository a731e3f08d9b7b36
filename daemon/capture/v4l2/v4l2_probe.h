// What `lumar probe` reports about V4L2 devices: identity, capabilities, and the formats and
// sizes each offers, read through the same ioctls the capture backend uses.
#pragma once

#include <string>
#include <vector>

#include "capture/v4l2/v4l2_format.h"

namespace lumar {

struct V4l2FormatInfo {
    std::string fourcc;
    bool convertible = false; // lumar can capture it (NV12, YUYV, MJPEG, GREY)
    std::vector<FrameSize> sizes;
};

struct V4l2DeviceInfo {
    std::string path;
    std::string card, driver, busInfo;
    bool streamingCapture = false;
    std::vector<V4l2FormatInfo> formats;
    std::string error; // set when the device could not be queried
};

// /dev/video* nodes, sorted.
std::vector<std::string> listVideoDevices();

// Never throws: a device that cannot be opened or queried has `error` set.
V4l2DeviceInfo probeV4l2Device(const std::string& path);

} // namespace lumar
