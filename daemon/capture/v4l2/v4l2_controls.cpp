#include "capture/v4l2/v4l2_controls.h"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <optional>

#include <linux/videodev2.h>

#include "capture/v4l2/v4l2_ioctl.h"
#include "core/log.h"

namespace lumar {
namespace {

struct Request {
    uint32_t id;
    const char* name;
    int32_t value;
};

// The device's description of control `id`, or nullopt (with a warning) when it lacks it.
std::optional<v4l2_queryctrl> describe(const std::string& device, int fd, const Request& request)
{
    v4l2_queryctrl query{};
    query.id = request.id;
    if (v4l2Ioctl(fd, VIDIOC_QUERYCTRL, &query) != 0 || (query.flags & V4L2_CTRL_FLAG_DISABLED)) {
        LUMAR_LOG(Capture, Warn) << device << ": the camera has no control for " << request.name << "; not set";
        return std::nullopt;
    }
    if (query.minimum > query.maximum) {
        // Nothing to clamp into (and std::clamp requires min <= max): a broken description.
        LUMAR_LOG(Capture, Warn) << device << ": the camera describes " << request.name << " with minimum "
                                 << query.minimum << " above maximum " << query.maximum << "; not set";
        return std::nullopt;
    }
    if (query.flags & V4L2_CTRL_FLAG_READ_ONLY) {
        LUMAR_LOG(Capture, Warn) << device << ": " << request.name << " is read-only on this camera; not set";
        return std::nullopt;
    }
    return query;
}

bool menuItemOffered(int fd, uint32_t id, int32_t index)
{
    v4l2_querymenu item{};
    item.id = id;
    item.index = uint32_t(index);
    return v4l2Ioctl(fd, VIDIOC_QUERYMENU, &item) == 0;
}

// The value to send: clamped into the device's range and snapped to its step (integers), or
// checked against the menu (menus). nullopt: nothing sensible to send.
std::optional<int32_t> fitToDevice(const std::string& device, int fd, const Request& request,
                                   const v4l2_queryctrl& query)
{
    if (query.type == V4L2_CTRL_TYPE_MENU) {
        if (request.value < query.minimum || request.value > query.maximum ||
            !menuItemOffered(fd, request.id, request.value)) {
            LUMAR_LOG(Capture, Warn) << device << ": " << request.name << ": the camera does not offer menu item "
                                     << request.value << "; not set";
            return std::nullopt;
        }
        return request.value;
    }
    int64_t value = std::clamp<int64_t>(request.value, query.minimum, query.maximum);
    if (query.step > 1) {
        value = query.minimum + (value - query.minimum + query.step / 2) / query.step * query.step;
        value = std::min<int64_t>(value, query.maximum);
    }
    if (request.value < query.minimum || request.value > query.maximum) {
        LUMAR_LOG(Capture, Warn) << device << ": " << request.name << " " << request.value
                                 << " is outside the camera's range [" << query.minimum << ", " << query.maximum
                                 << "]; clamped to " << value;
    } else if (value != request.value) {
        LUMAR_LOG(Capture, Info) << device << ": " << request.name << " " << request.value
                                 << " rounded to the camera's step of " << query.step << ": " << value;
    }
    return int32_t(value);
}

// What the config asks for, in the order it must be applied: each automatic mode is switched
// before the manual value it unlocks.
std::vector<Request> requestsFor(int fd, const CameraControlsConfig& config)
{
    std::vector<Request> requests;
    if (config.exposureUs) {
        if (*config.exposureUs == CameraControlsConfig::kAuto) {
            // UVC cameras offer aperture priority (auto exposure, fixed iris) rather than full auto.
            const bool fullAuto = menuItemOffered(fd, V4L2_CID_EXPOSURE_AUTO, V4L2_EXPOSURE_AUTO);
            requests.push_back({V4L2_CID_EXPOSURE_AUTO, "exposure_us (auto exposure)",
                                fullAuto ? V4L2_EXPOSURE_AUTO : V4L2_EXPOSURE_APERTURE_PRIORITY});
        } else {
            requests.push_back({V4L2_CID_EXPOSURE_AUTO, "exposure_us (auto exposure off)", V4L2_EXPOSURE_MANUAL});
            // V4L2's absolute exposure counts 100 µs units.
            const auto units = int32_t(std::max(1L, std::lround(*config.exposureUs / 100.0)));
            requests.push_back({V4L2_CID_EXPOSURE_ABSOLUTE, "exposure_us (absolute exposure, 100 us units)", units});
        }
    }
    if (config.gain) {
        requests.push_back({V4L2_CID_GAIN, "gain", *config.gain});
    }
    if (config.whiteBalanceK) {
        const bool automatic = *config.whiteBalanceK == CameraControlsConfig::kAuto;
        requests.push_back({V4L2_CID_AUTO_WHITE_BALANCE, "white_balance_k (auto white balance)", automatic ? 1 : 0});
        if (!automatic) {
            requests.push_back({V4L2_CID_WHITE_BALANCE_TEMPERATURE, "white_balance_k (white balance temperature)",
                                *config.whiteBalanceK});
        }
    }
    if (config.powerLineHz) {
        const int32_t item = *config.powerLineHz == 50   ? V4L2_CID_POWER_LINE_FREQUENCY_50HZ
                             : *config.powerLineHz == 60 ? V4L2_CID_POWER_LINE_FREQUENCY_60HZ
                                                         : V4L2_CID_POWER_LINE_FREQUENCY_DISABLED;
        requests.push_back({V4L2_CID_POWER_LINE_FREQUENCY, "power_line_hz (power line frequency)", item});
    }
    return requests;
}

} // namespace

std::vector<AppliedControl> applyCameraControls(const std::string& device, int fd, const CameraControlsConfig& config)
{
    std::vector<AppliedControl> applied;
    std::vector<v4l2_ext_control> batch;
    for (const Request& request : requestsFor(fd, config)) {
        const auto query = describe(device, fd, request);
        if (!query) {
            applied.push_back({request.id, request.name, request.value, request.value, false});
            continue;
        }
        const auto value = fitToDevice(device, fd, request, *query);
        if (!value) {
            applied.push_back({request.id, request.name, request.value, request.value, false});
            continue;
        }
        applied.push_back({request.id, request.name, request.value, *value, false});
        v4l2_ext_control control{};
        control.id = request.id;
        control.value = *value;
        batch.push_back(control);
    }
    if (batch.empty()) {
        return applied;
    }
    v4l2_ext_controls controls{};
    controls.which = V4L2_CTRL_WHICH_CUR_VAL;
    controls.count = uint32_t(batch.size());
    controls.controls = batch.data();
    const bool batched = v4l2Ioctl(fd, VIDIOC_S_EXT_CTRLS, &controls) == 0;
    for (AppliedControl& control : applied) {
        const bool inBatch = std::any_of(batch.begin(), batch.end(), [&](const v4l2_ext_control& c) {
            return c.id == control.id && c.value == control.value;
        });
        if (!inBatch) {
            continue;
        }
        if (!batched) {
            // One by one, so one refused control does not take the others with it.
            v4l2_control single{control.id, control.value};
            const int error = v4l2Ioctl(fd, VIDIOC_S_CTRL, &single);
            if (error != 0) {
                LUMAR_LOG(Capture, Warn) << device << ": setting " << control.name << " to " << control.value
                                         << " failed: " << std::strerror(error);
                continue;
            }
        }
        control.set = true;
        LUMAR_LOG(Capture, Info) << device << ": " << control.name << " = " << control.value;
    }
    return applied;
}

} // namespace lumar
