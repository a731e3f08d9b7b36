// lumar's side of the V4L2 ioctl conversation with a driver whose answers come from the input,
// as a broken or hostile driver (or a USB device lying through uvcvideo) might give them: the
// format and frame-size enumerations and the choices made from them, and the camera controls
// checked against the device's descriptions (VIDIOC_QUERYCTRL, QUERYMENU) and set
// (S_EXT_CTRLS, S_CTRL). The functions are the ones V4l2Source calls
// (capture/v4l2/v4l2_format.h, v4l2_controls.h); only ioctl() is replaced, for one made-up
// descriptor. The negotiated format and the buffers are fuzz_v4l2_frame's.
//
// Input: a 12-byte header, then the driver's answers, read in turn by each ioctl and read
// again from the start when they run out (a driver repeating itself forever: lumar must end
// every enumeration on its own):
//   u8 required format (0: any, else 1 + index into NV12 YUYV MJPEG GREY)
//   u16 requested width, u16 requested height
//   u8 controls present (bit 0 exposure, 1 gain, 2 white balance, 3 power line; bit 4:
//      exposure auto, bit 5: white balance auto)
//   u16 exposure (µs, x 10), u16 gain (signed), u16 white balance (K)
// Each answer: u8 outcome (low 3 bits: 0 EINVAL, 1 ENOTTY, 2 EIO, 3 ENODEV, 4 EINTR once
// then again, else success), then for a success the fields below, little-endian.
#include <algorithm>
#include <cerrno>
#include <cstdarg>
#include <cstring>
#include <utility>
#include <vector>

#include <linux/videodev2.h>
#include <sys/ioctl.h>
#include <sys/syscall.h>
#include <unistd.h>

#include "capture/v4l2/v4l2_controls.h"
#include "capture/v4l2/v4l2_format.h"
#include "core/error.h"
#include "fuzz_support.h"

namespace {

constexpr int kDriverFd = 1'000'003; // no real descriptor has this number here
constexpr size_t kHeaderBytes = 12;

// The driver: its answers, read cyclically.
struct Driver {
    const uint8_t* answers = nullptr;
    size_t size = 0;
    size_t at = 0;
    size_t calls = 0;
    bool interrupted = false; // the last answer was EINTR

    uint8_t byte()
    {
        if (size == 0)
            return 0;
        const uint8_t b = answers[at];
        at = (at + 1) % size;
        return b;
    }
    uint32_t u32()
    {
        uint32_t v = 0;
        for (int i = 0; i < 4; ++i)
            v |= uint32_t(byte()) << (8 * i);
        return v;
    }
    int32_t s32() { return int32_t(u32()); }
};

Driver gDriver;

// What the driver does with one request; 0 or an errno.
int answer(unsigned long request, void* arg)
{
    Driver& d = gDriver;
    ++d.calls;
    const uint8_t outcome = d.byte() & 7;
    if (outcome != 4)
        d.interrupted = false;
    switch (outcome) {
    case 0:
        return EINVAL;
    case 1:
        return ENOTTY;
    case 2:
        return EIO;
    case 3:
        return ENODEV;
    case 4:
        // Interrupted (v4l2Ioctl asks again). A kernel says EINTR for a signal, not forever:
        // never twice in a row (a driver answering only EINTR kept the target busy for ever).
        if (!std::exchange(d.interrupted, true))
            return EINTR;
        break;
    default:
        break;
    }
    switch (request) {
    case VIDIOC_ENUM_FMT: {
        auto* description = static_cast<v4l2_fmtdesc*>(arg);
        description->pixelformat = d.u32();
        description->flags = d.u32();
        return 0;
    }
    case VIDIOC_ENUM_FRAMESIZES: {
        auto* size = static_cast<v4l2_frmsizeenum*>(arg);
        size->type = d.u32() % 4; // 1..3 are V4L2's types, 0 is none of them
        if (size->type == V4L2_FRMSIZE_TYPE_DISCRETE) {
            size->discrete.width = d.u32();
            size->discrete.height = d.u32();
        } else {
            size->stepwise.min_width = d.u32();
            size->stepwise.max_width = d.u32();
            size->stepwise.step_width = d.u32();
            size->stepwise.min_height = d.u32();
            size->stepwise.max_height = d.u32();
            size->stepwise.step_height = d.u32();
        }
        return 0;
    }
    case VIDIOC_QUERYCTRL: {
        auto* query = static_cast<v4l2_queryctrl*>(arg);
        query->type = d.u32() % 8;
        query->minimum = d.s32();
        query->maximum = d.s32();
        query->step = d.s32();
        query->default_value = d.s32();
        query->flags = d.u32();
        return 0;
    }
    case VIDIOC_QUERYMENU:
    case VIDIOC_S_EXT_CTRLS:
    case VIDIOC_S_CTRL:
        return 0;
    default:
        return ENOTTY;
    }
}

} // namespace

// The one ioctl() of this program: the made-up descriptor is the driver above, the rest go
// to the kernel.
extern "C" int ioctl(int fd, unsigned long request, ...) __THROW
{
    va_list args;
    va_start(args, request);
    void* arg = va_arg(args, void*);
    va_end(args);
    if (fd != kDriverFd)
        return int(::syscall(SYS_ioctl, fd, request, arg));
    const int error = answer(request, arg);
    if (error != 0) {
        errno = error;
        return -1;
    }
    return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size)
{
    (void)lumar::fuzz::scratchDir(); // logs off
    if (size < kHeaderBytes)
        return 0;
    const auto u16 = [&](size_t at) { return uint16_t(data[at] | data[at + 1] << 8); };
    static const uint32_t kFormats[] = {V4L2_PIX_FMT_NV12, V4L2_PIX_FMT_YUYV, V4L2_PIX_FMT_MJPEG, V4L2_PIX_FMT_GREY};
    const uint32_t required = data[0] % 5 == 0 ? 0 : kFormats[data[0] % 5 - 1];
    const lumar::FrameSize requested{u16(1), u16(3)};
    lumar::CameraControlsConfig controls;
    if (data[5] & 1)
        controls.exposureUs = (data[5] & 16) ? lumar::CameraControlsConfig::kAuto : int(u16(6)) * 10;
    if (data[5] & 2)
        controls.gain = int16_t(u16(8));
    if (data[5] & 4)
        controls.whiteBalanceK = (data[5] & 32) ? lumar::CameraControlsConfig::kAuto : int(u16(10));
    if (data[5] & 8)
        controls.powerLineHz = (data[5] & 64) ? 50 : 60;
    gDriver = Driver{data + kHeaderBytes, size - kHeaderBytes, 0, 0, false};

    const std::string device = "/dev/fuzz";
    try {
        const std::vector<uint32_t> formats = lumar::enumeratePixelFormats(device, kDriverFd);
        if (formats.size() > lumar::kMaxV4l2Formats)
            __builtin_trap();
        const uint32_t format = lumar::choosePixelFormat(formats, required);
        if (format == 0)
            throw lumar::RuntimeError(device + ": no format lumar converts"); // as V4l2Source does
        const std::vector<lumar::FrameSize> sizes = lumar::enumerateFrameSizes(device, kDriverFd, format, requested);
        if (sizes.empty() || sizes.size() > lumar::kMaxV4l2FrameSizes)
            __builtin_trap();
        (void)lumar::chooseFrameSize(sizes, requested);
    } catch (const lumar::RuntimeError&) {
        // A device failure or no format lumar converts: the source refuses the camera.
    } catch (const lumar::InputError&) {
    }
    // Controls never throw: each problem is a warning and the control is skipped.
    for (const lumar::AppliedControl& applied : lumar::applyCameraControls(device, kDriverFd, controls)) {
        (void)applied;
    }
    return 0;
}
