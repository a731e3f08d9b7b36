#include "capture/v4l2/v4l2_ioctl.h"

#include <cerrno>
#include <cstring>

#include <sys/ioctl.h>

#include "core/error.h"

namespace lumar {

int v4l2Ioctl(int fd, unsigned long request, void* arg)
{
    for (;;) {
        if (::ioctl(fd, request, arg) == 0) {
            return 0;
        }
        if (errno != EINTR) {
            return errno;
        }
    }
}

void throwDeviceError(const std::string& device, const char* what, int error)
{
    if (error == ENODEV) {
        throw RuntimeError(device + ": " + what + " failed: the device was unplugged (ENODEV)");
    }
    throw RuntimeError(device + ": " + what + " failed: " + std::strerror(error));
}

void v4l2IoctlOrThrow(const std::string& device, int fd, unsigned long request, void* arg, const char* what)
{
    if (const int error = v4l2Ioctl(fd, request, arg); error != 0) {
        throwDeviceError(device, what, error);
    }
}

std::string fourccName(unsigned fourcc)
{
    std::string name;
    for (int i = 0; i < 4; ++i) {
        const char c = char((fourcc >> (8 * i)) & 0xffu);
        name += (c >= 32 && c < 127) ? c : '?';
    }
    return name;
}

} // namespace lumar
