#include "vcam/vcam_controls.h"

#include <algorithm>
#include <cerrno>
#include <cstring>

namespace lumar::vcam {
namespace {

// The kernel's own names (v4l2-ctrls-defs.c), so tools show what they show for a real camera.
const char* const kExposureModes[] = {"Auto Mode", "Manual Mode", "Shutter Priority Mode", "Aperture Priority Mode"};
const char* const kPowerLineModes[] = {"Disabled", "50 Hz", "60 Hz"};

constexpr uint32_t kClassFlags = V4L2_CTRL_FLAG_READ_ONLY | V4L2_CTRL_FLAG_WRITE_ONLY;

void copyName(char* out, size_t capacity, const char* text)
{
    std::memset(out, 0, capacity);
    std::strncpy(out, text, capacity - 1);
}

} // namespace

ControlSet::ControlSet()
{
    controls_ = {
        {V4L2_CID_USER_CLASS, V4L2_CTRL_TYPE_CTRL_CLASS, "User Controls", 0, 0, 0, 0, kClassFlags, 0, nullptr, 0},
        {V4L2_CID_AUTO_WHITE_BALANCE, V4L2_CTRL_TYPE_BOOLEAN, "White Balance, Automatic", 0, 1, 1, 1,
         V4L2_CTRL_FLAG_UPDATE, 0, nullptr, 1},
        {V4L2_CID_GAIN, V4L2_CTRL_TYPE_INTEGER, "Gain", 0, 255, 1, 32, 0, 0, nullptr, 32},
        {V4L2_CID_POWER_LINE_FREQUENCY, V4L2_CTRL_TYPE_MENU, "Power Line Frequency", 0, 2, 1, 1, 0, 0, kPowerLineModes,
         1},
        {V4L2_CID_WHITE_BALANCE_TEMPERATURE, V4L2_CTRL_TYPE_INTEGER, "White Balance Temperature", 2800, 6500, 10, 4600,
         0, 0, nullptr, 4600},
        {V4L2_CID_CAMERA_CLASS, V4L2_CTRL_TYPE_CTRL_CLASS, "Camera Controls", 0, 0, 0, 0, kClassFlags, 0, nullptr, 0},
        // A UVC camera offers manual and aperture priority only.
        {V4L2_CID_EXPOSURE_AUTO, V4L2_CTRL_TYPE_MENU, "Auto Exposure", 0, 3, 1, V4L2_EXPOSURE_APERTURE_PRIORITY,
         V4L2_CTRL_FLAG_UPDATE, (1u << V4L2_EXPOSURE_AUTO) | (1u << V4L2_EXPOSURE_SHUTTER_PRIORITY), kExposureModes,
         V4L2_EXPOSURE_APERTURE_PRIORITY},
        // 100 µs units: 0.3 ms .. 204.7 ms.
        {V4L2_CID_EXPOSURE_ABSOLUTE, V4L2_CTRL_TYPE_INTEGER, "Exposure Time, Absolute", 3, 2047, 1, 250, 0, 0, nullptr,
         250},
    };
}

const ControlSet::Control* ControlSet::find(uint32_t id) const
{
    const auto found = std::find_if(controls_.begin(), controls_.end(), [&](const Control& c) { return c.id == id; });
    return found == controls_.end() ? nullptr : &*found;
}

ControlSet::Control* ControlSet::find(uint32_t id)
{
    const auto found = std::find_if(controls_.begin(), controls_.end(), [&](const Control& c) { return c.id == id; });
    return found == controls_.end() ? nullptr : &*found;
}

bool ControlSet::isClass(uint32_t id) const
{
    const Control* control = find(id);
    return control != nullptr && control->type == V4L2_CTRL_TYPE_CTRL_CLASS;
}

const ControlSet::Control* ControlSet::lookup(uint32_t id) const
{
    const uint32_t next = id & (V4L2_CTRL_FLAG_NEXT_CTRL | V4L2_CTRL_FLAG_NEXT_COMPOUND);
    const uint32_t bare = id & ~(V4L2_CTRL_FLAG_NEXT_CTRL | V4L2_CTRL_FLAG_NEXT_COMPOUND);
    if (next == 0) {
        return find(bare);
    }
    if (!(next & V4L2_CTRL_FLAG_NEXT_CTRL)) {
        return nullptr; // only compound controls asked for: this device has none
    }
    for (const Control& control : controls_) {
        if (control.id > bare) {
            return &control;
        }
    }
    return nullptr;
}

uint32_t ControlSet::flags(const Control& control) const
{
    uint32_t result = control.baseFlags;
    if (control.id == V4L2_CID_WHITE_BALANCE_TEMPERATURE && find(V4L2_CID_AUTO_WHITE_BALANCE)->value != 0) {
        result |= V4L2_CTRL_FLAG_INACTIVE;
    }
    if (control.id == V4L2_CID_EXPOSURE_ABSOLUTE && find(V4L2_CID_EXPOSURE_AUTO)->value != V4L2_EXPOSURE_MANUAL) {
        result |= V4L2_CTRL_FLAG_INACTIVE;
    }
    return result;
}

int ControlSet::query(v4l2_queryctrl& query) const
{
    const Control* control = lookup(query.id);
    if (control == nullptr) {
        return EINVAL;
    }
    std::memset(&query, 0, sizeof query);
    query.id = control->id;
    query.type = control->type;
    copyName(reinterpret_cast<char*>(query.name), sizeof query.name, control->name);
    query.minimum = control->minimum;
    query.maximum = control->maximum;
    query.step = control->step;
    query.default_value = control->defaultValue;
    query.flags = flags(*control);
    return 0;
}

int ControlSet::queryExtended(v4l2_query_ext_ctrl& query) const
{
    const Control* control = lookup(query.id);
    if (control == nullptr) {
        return EINVAL;
    }
    std::memset(&query, 0, sizeof query);
    query.id = control->id;
    query.type = control->type;
    copyName(query.name, sizeof query.name, control->name);
    query.minimum = control->minimum;
    query.maximum = control->maximum;
    query.step = uint64_t(control->step);
    query.default_value = control->defaultValue;
    query.flags = flags(*control);
    query.elem_size = control->type == V4L2_CTRL_TYPE_CTRL_CLASS ? 0 : sizeof(int32_t);
    query.elems = 1;
    return 0;
}

int ControlSet::queryMenu(v4l2_querymenu& item) const
{
    const Control* control = find(item.id);
    if (control == nullptr || control->type != V4L2_CTRL_TYPE_MENU || item.index < uint32_t(control->minimum) ||
        item.index > uint32_t(control->maximum) || (control->menuSkip & (1ull << item.index))) {
        return EINVAL;
    }
    const uint32_t id = item.id;
    const uint32_t index = item.index;
    std::memset(&item, 0, sizeof item);
    item.id = id;
    item.index = index;
    copyName(reinterpret_cast<char*>(item.name), sizeof item.name, control->menuNames[index]);
    return 0;
}

int ControlSet::validate(const Control& control, int32_t& requested) const
{
    switch (control.type) {
    case V4L2_CTRL_TYPE_BOOLEAN:
        requested = requested != 0 ? 1 : 0;
        return 0;
    case V4L2_CTRL_TYPE_MENU:
        if (requested < control.minimum || requested > control.maximum) {
            return ERANGE;
        }
        return (control.menuSkip & (1ull << requested)) ? EINVAL : 0;
    default: {
        int64_t value = std::clamp<int64_t>(requested, control.minimum, control.maximum);
        value = control.minimum + (value - control.minimum + control.step / 2) / control.step * control.step;
        requested = int32_t(std::min<int64_t>(value, control.maximum));
        return 0;
    }
    }
}

bool ControlSet::describe(uint32_t id, v4l2_event_ctrl& state) const
{
    const Control* control = find(id);
    if (control == nullptr) {
        return false;
    }
    std::memset(&state, 0, sizeof state);
    state.type = control->type;
    state.value = control->value;
    state.flags = flags(*control);
    state.minimum = control->minimum;
    state.maximum = control->maximum;
    state.step = control->step;
    state.default_value = control->defaultValue;
    return true;
}

void ControlSet::store(Control& control, int32_t value, const ChangeListener& changed)
{
    if (control.value == value) {
        return;
    }
    // The manual control an automatic mode governs changes its "inactive" flag with it.
    const uint32_t dependent = control.id == V4L2_CID_AUTO_WHITE_BALANCE ? V4L2_CID_WHITE_BALANCE_TEMPERATURE
                               : control.id == V4L2_CID_EXPOSURE_AUTO    ? V4L2_CID_EXPOSURE_ABSOLUTE
                                                                         : 0;
    const uint32_t dependentFlagsBefore = dependent != 0 ? flags(*find(dependent)) : 0;
    control.value = value;
    v4l2_event_ctrl state{};
    if (changed && describe(control.id, state)) {
        changed(state, control.id, V4L2_EVENT_CTRL_CH_VALUE);
    }
    if (dependent != 0 && changed && flags(*find(dependent)) != dependentFlagsBefore && describe(dependent, state)) {
        changed(state, dependent, V4L2_EVENT_CTRL_CH_FLAGS);
    }
}

int ControlSet::get(v4l2_control& control) const
{
    const Control* found = find(control.id);
    if (found == nullptr) {
        return EINVAL;
    }
    if (found->type == V4L2_CTRL_TYPE_CTRL_CLASS) {
        return EACCES; // write-only, as the kernel answers for a class
    }
    control.value = found->value;
    return 0;
}

int ControlSet::set(v4l2_control& control, const ChangeListener& changed)
{
    Control* found = find(control.id);
    if (found == nullptr) {
        return EINVAL;
    }
    if (found->type == V4L2_CTRL_TYPE_CTRL_CLASS) {
        return EACCES; // read-only
    }
    int32_t value = control.value;
    if (const int error = validate(*found, value); error != 0) {
        return error;
    }
    store(*found, value, changed);
    control.value = value;
    return 0;
}

int ControlSet::getExtended(v4l2_ext_controls& controls) const
{
    const uint32_t which = controls.which;
    const bool defaults = which == V4L2_CTRL_WHICH_DEF_VAL;
    const bool isClassWhich = which != V4L2_CTRL_WHICH_CUR_VAL && !defaults;
    if (isClassWhich && which != V4L2_CTRL_CLASS_USER && which != V4L2_CTRL_CLASS_CAMERA) {
        return EINVAL;
    }
    if (controls.count == 0) {
        return 0;
    }
    if (controls.controls == nullptr) {
        return EFAULT;
    }
    controls.error_idx = controls.count; // a failure before any value was read
    for (uint32_t i = 0; i < controls.count; ++i) {
        const v4l2_ext_control& request = controls.controls[i];
        const Control* found = find(request.id);
        if (found == nullptr || (isClassWhich && V4L2_CTRL_ID2WHICH(request.id) != which)) {
            return EINVAL;
        }
        if (found->type == V4L2_CTRL_TYPE_CTRL_CLASS) {
            return EACCES;
        }
    }
    for (uint32_t i = 0; i < controls.count; ++i) {
        v4l2_ext_control& out = controls.controls[i];
        const Control* found = find(out.id);
        out.value = defaults ? found->defaultValue : found->value;
    }
    controls.error_idx = 0;
    return 0;
}

int ControlSet::setExtended(v4l2_ext_controls& controls, bool apply, const ChangeListener& changed)
{
    const uint32_t which = controls.which;
    if (which == V4L2_CTRL_WHICH_DEF_VAL || which == V4L2_CTRL_WHICH_REQUEST_VAL) {
        return EINVAL;
    }
    const bool isClassWhich = which != V4L2_CTRL_WHICH_CUR_VAL;
    if (isClassWhich && which != V4L2_CTRL_CLASS_USER && which != V4L2_CTRL_CLASS_CAMERA) {
        return EINVAL;
    }
    if (controls.count == 0) {
        return 0;
    }
    if (controls.controls == nullptr) {
        return EFAULT;
    }
    // The kernel reports a failed check at its index for TRY, at `count` for SET (nothing set).
    const auto failAt = [&](uint32_t i, int error) {
        controls.error_idx = apply ? controls.count : i;
        return error;
    };
    std::vector<int32_t> values(controls.count);
    for (uint32_t i = 0; i < controls.count; ++i) {
        const v4l2_ext_control& request = controls.controls[i];
        const Control* found = find(request.id);
        if (found == nullptr || (isClassWhich && V4L2_CTRL_ID2WHICH(request.id) != which)) {
            return failAt(i, EINVAL);
        }
        if (found->type == V4L2_CTRL_TYPE_CTRL_CLASS) {
            return failAt(i, EACCES);
        }
        values[i] = request.value;
        if (const int error = validate(*found, values[i]); error != 0) {
            return failAt(i, error);
        }
    }
    for (uint32_t i = 0; i < controls.count; ++i) {
        controls.controls[i].value = values[i];
        if (apply) {
            store(*find(controls.controls[i].id), values[i], changed);
        }
    }
    controls.error_idx = 0;
    return 0;
}

} // namespace lumar::vcam
