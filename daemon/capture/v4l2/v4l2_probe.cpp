#include "capture/v4l2/v4l2_probe.h"

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <filesystem>

#include <fcntl.h>
#include <linux/videodev2.h>

#include "capture/v4l2/v4l2_ioctl.h"
#include "core/error.h"
#include "core/unique_fd.h"

namespace lumar {

std::vector<std::string> listVideoDevices()
{
    std::vector<std::string> devices;
    std::error_code ec;
    for (const auto& entry : std::filesystem::directory_iterator("/dev", ec)) {
        const std::string name = entry.path().filename().string();
        if (name.rfind("video", 0) == 0)
            devices.push_back(entry.path().string());
    }
    std::sort(devices.begin(), devices.end());
    return devices;
}

V4l2DeviceInfo probeV4l2Device(const std::string& path)
{
    V4l2DeviceInfo info;
    info.path = path;
    const UniqueFd fd(::open(path.c_str(), O_RDWR | O_NONBLOCK | O_CLOEXEC));
    if (!fd.valid()) {
        info.error = std::string("cannot open: ") + std::strerror(errno);
        return info;
    }
    try {
        v4l2_capability caps{};
        v4l2IoctlOrThrow(path, fd.get(), VIDIOC_QUERYCAP, &caps, "VIDIOC_QUERYCAP");
        info.card = reinterpret_cast<const char*>(caps.card);
        info.driver = reinterpret_cast<const char*>(caps.driver);
        info.busInfo = reinterpret_cast<const char*>(caps.bus_info);
        const uint32_t deviceCaps = (caps.capabilities & V4L2_CAP_DEVICE_CAPS) ? caps.device_caps : caps.capabilities;
        info.streamingCapture = (deviceCaps & V4L2_CAP_VIDEO_CAPTURE) && (deviceCaps & V4L2_CAP_STREAMING);
        if (!info.streamingCapture)
            return info;
        const auto& supported = supportedPixelFormats();
        for (uint32_t fourcc : enumeratePixelFormats(path, fd.get())) {
            V4l2FormatInfo format;
            format.fourcc = fourccName(fourcc);
            format.convertible = std::find(supported.begin(), supported.end(), fourcc) != supported.end();
            format.sizes = enumerateFrameSizes(path, fd.get(), fourcc, {1280, 720});
            info.formats.push_back(std::move(format));
        }
    } catch (const RuntimeError& e) {
        info.error = e.what();
    }
    return info;
}

} // namespace lumar
