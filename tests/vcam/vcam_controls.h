// The virtual camera's controls, as a UVC webcam's driver exposes them: exposure (auto mode
// menu and absolute time), gain, white balance (auto and temperature) and power-line
// frequency, with their control classes. Serves VIDIOC_QUERYCTRL, QUERY_EXT_CTRL, QUERYMENU,
// G/S_CTRL and G/S/TRY_EXT_CTRLS with the kernel's rules: integers are clamped into range and
// snapped to the step, menus reject items they lack, class controls are neither readable nor
// writable, and a manual value is "inactive" while its automatic mode is on.
#pragma once

#include <cstdint>
#include <functional>
#include <vector>

#include <linux/videodev2.h>

namespace lumar::vcam {

class ControlSet {
public:
    // Told about every change of a control's value (changes V4L2_EVENT_CTRL_CH_VALUE) or flags
    // (V4L2_EVENT_CTRL_CH_FLAGS), to raise control events.
    using ChangeListener = std::function<void(const v4l2_event_ctrl& state, uint32_t id, uint32_t changes)>;

    ControlSet();

    // Each returns 0 or an errno, as the ioctl would.
    int query(v4l2_queryctrl& query) const;
    int queryExtended(v4l2_query_ext_ctrl& query) const;
    int queryMenu(v4l2_querymenu& item) const;
    int get(v4l2_control& control) const;
    int set(v4l2_control& control, const ChangeListener& changed);
    int getExtended(v4l2_ext_controls& controls) const;
    int setExtended(v4l2_ext_controls& controls, bool apply, const ChangeListener& changed);

    // The event payload describing control `id` now; false when there is no such control.
    bool describe(uint32_t id, v4l2_event_ctrl& state) const;
    [[nodiscard]] bool isClass(uint32_t id) const;

private:
    struct Control {
        uint32_t id;
        uint32_t type;
        const char* name;
        int32_t minimum;
        int32_t maximum;
        int32_t step;
        int32_t defaultValue;
        uint32_t baseFlags;
        uint64_t menuSkip; // menu items the device lacks (bit i: item i)
        const char* const* menuNames;
        int32_t value;
    };

    [[nodiscard]] const Control* find(uint32_t id) const;
    Control* find(uint32_t id);
    // The control after `id` when `id` carries V4L2_CTRL_FLAG_NEXT_CTRL, else `id` itself.
    [[nodiscard]] const Control* lookup(uint32_t id) const;
    [[nodiscard]] uint32_t flags(const Control& control) const;
    // The value `requested` becomes (clamped, snapped); an errno for an invalid menu item.
    int validate(const Control& control, int32_t& requested) const;
    void store(Control& control, int32_t value, const ChangeListener& changed);

    std::vector<Control> controls_; // sorted by id
};

} // namespace lumar::vcam
