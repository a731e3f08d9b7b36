// Makes the served path look like a V4L2 character device node to tools that inspect the
// node before opening it: v4l2-compliance stat()s the path and reads
// /sys/dev/char/MAJOR:MINOR/uevent to learn that it is a "video" node. Both answers are
// synthesised here (major 81, the minor from the path's trailing digits); every other path
// goes to the C library.
#include <cctype>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <string>
#include <string_view>

#include <sys/mman.h>
#include <sys/stat.h>
#include <sys/sysmacros.h>
#include <unistd.h>

#include "vcam/real_libc.h"
#include "vcam/vcam_settings.h"

namespace lumar::vcam {
namespace {

constexpr unsigned kVideoMajor = 81; // the kernel's video4linux character major

// The minor number: the path's trailing digits (/dev/video7 → 7), 0 when it has none.
unsigned servedMinor(const std::string& path)
{
    size_t start = path.size();
    while (start > 0 && std::isdigit(static_cast<unsigned char>(path[start - 1]))) {
        --start;
    }
    return start == path.size() ? 0u : unsigned(std::stoul(path.substr(start)));
}

bool isServedNode(const char* path, unsigned& minor)
{
    if (path == nullptr) {
        return false;
    }
    const Settings settings = settingsFromEnvironment();
    if (std::string_view(path) != settings.devicePath) {
        return false;
    }
    minor = servedMinor(settings.devicePath);
    return true;
}

template <typename StatBuffer> void describeNode(unsigned minor, StatBuffer* out)
{
    std::memset(out, 0, sizeof *out);
    out->st_mode = S_IFCHR | 0660;
    out->st_rdev = makedev(kVideoMajor, minor);
    out->st_nlink = 1;
    out->st_blksize = 4096;
}

// The uevent file of the served node, when `path` names it: a memfd holding its text.
FILE* openUevent(const char* path)
{
    const Settings settings = settingsFromEnvironment();
    const unsigned minor = servedMinor(settings.devicePath);
    const std::string uevent = "/sys/dev/char/" + std::to_string(kVideoMajor) + ":" + std::to_string(minor) + "/uevent";
    if (path == nullptr || uevent != path) {
        return nullptr;
    }
    const std::string text = "MAJOR=" + std::to_string(kVideoMajor) + "\nMINOR=" + std::to_string(minor) +
                             "\nDEVNAME=video" + std::to_string(minor) + "\n";
    const int fd = memfd_create("lumar-vcam-uevent", MFD_CLOEXEC);
    if (fd < 0) {
        return nullptr;
    }
    if (::write(fd, text.data(), text.size()) != ssize_t(text.size()) || ::lseek(fd, 0, SEEK_SET) != 0) {
        real::close(fd);
        return nullptr;
    }
    FILE* file = ::fdopen(fd, "r");
    if (file == nullptr) {
        real::close(fd);
    }
    return file;
}

} // namespace
} // namespace lumar::vcam

using namespace lumar::vcam;

extern "C" {

__attribute__((visibility("default"))) int stat(const char* path, struct stat* out) noexcept
{
    if (unsigned minor = 0; isServedNode(path, minor)) {
        describeNode(minor, out);
        return 0;
    }
    return real::stat(path, out);
}

__attribute__((visibility("default"))) int stat64(const char* path, struct stat64* out) noexcept
{
    if (unsigned minor = 0; isServedNode(path, minor)) {
        describeNode(minor, out);
        return 0;
    }
    return real::stat64(path, out);
}

__attribute__((visibility("default"))) FILE* fopen(const char* path, const char* mode)
{
    if (FILE* uevent = openUevent(path)) {
        return uevent;
    }
    return real::fopen(path, mode);
}

__attribute__((visibility("default"))) FILE* fopen64(const char* path, const char* mode)
{
    if (FILE* uevent = openUevent(path)) {
        return uevent;
    }
    return real::fopen64(path, mode);
}

} // extern "C"
