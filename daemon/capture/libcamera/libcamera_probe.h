// What `lumar probe` reports about libcamera cameras: each camera's id and model, and the
// pixel formats and sizes its Viewfinder stream offers, read through the same camera manager
// the capture backend uses.
#pragma once

#include <string>
#include <vector>

#include "capture/v4l2/v4l2_format.h"

namespace lumar {

struct LibcameraFormatInfo {
    std::string pixelFormat;      // libcamera's name, e.g. "NV12"
    bool convertible = false;     // lumar can capture it (convertibleLibcameraFormats)
    std::vector<FrameSize> sizes; // the discrete sizes; empty when only a range is known
    FrameSize minSize, maxSize;   // the range of sizes
};

struct LibcameraCameraInfo {
    std::string id;
    std::string model;         // the Model property; empty when the camera has none
    std::string defaultStream; // the Viewfinder configuration as generated, e.g. "1280x720-NV12"
    std::vector<LibcameraFormatInfo> formats;
    std::string error; // set when the camera could not be queried
};

struct LibcameraProbeInfo {
    std::string version; // "libcamera v0.0.3"
    std::vector<LibcameraCameraInfo> cameras;
    std::string error; // set when libcamera could not start, or found no cameras
};

// Never throws.
LibcameraProbeInfo probeLibcamera();

} // namespace lumar
