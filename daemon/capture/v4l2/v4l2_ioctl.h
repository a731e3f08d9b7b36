// ioctl() on a V4L2 node with the two conventions every caller needs: retry on EINTR, and a
// RuntimeError whose message names the device and says "unplugged" for ENODEV.
#pragma once

#include <string>

namespace lumar {

// Returns 0 or the errno of the failed call (after retrying EINTR).
int v4l2Ioctl(int fd, unsigned long request, void* arg);

// Throws RuntimeError "DEVICE: WHAT failed: REASON" (ENODEV: the device was unplugged).
[[noreturn]] void throwDeviceError(const std::string& device, const char* what, int error);

// v4l2Ioctl that throws on any failure.
void v4l2IoctlOrThrow(const std::string& device, int fd, unsigned long request, void* arg, const char* what);

// "YUYV" for a fourcc code, for log lines and messages.
std::string fourccName(unsigned fourcc);

} // namespace lumar
