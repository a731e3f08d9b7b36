#include "vcam/real_libc.h"

#include <cerrno>

#include <dlfcn.h>
#include <sys/mman.h>

namespace lumar::vcam::real {
namespace {

// Resolved once per symbol (thread-safe static initialisation); null only if the C library
// lacks the symbol, which the callers report as ENOSYS instead of crashing.
template <typename Function> Function* next(const char* name)
{
    return reinterpret_cast<Function*>(dlsym(RTLD_NEXT, name));
}

} // namespace

int open(const char* path, int flags, mode_t mode)
{
    static auto* const function = next<int(const char*, int, ...)>("open");
    if (function == nullptr) {
        errno = ENOSYS;
    }
    return function ? function(path, flags, mode) : -1;
}

int open64(const char* path, int flags, mode_t mode)
{
    static auto* const function = next<int(const char*, int, ...)>("open64");
    if (function == nullptr) {
        errno = ENOSYS;
    }
    return function ? function(path, flags, mode) : -1;
}

int openat(int directory, const char* path, int flags, mode_t mode)
{
    static auto* const function = next<int(int, const char*, int, ...)>("openat");
    if (function == nullptr) {
        errno = ENOSYS;
    }
    return function ? function(directory, path, flags, mode) : -1;
}

int openat64(int directory, const char* path, int flags, mode_t mode)
{
    static auto* const function = next<int(int, const char*, int, ...)>("openat64");
    if (function == nullptr) {
        errno = ENOSYS;
    }
    return function ? function(directory, path, flags, mode) : -1;
}

int close(int fd)
{
    static auto* const function = next<int(int)>("close");
    if (function == nullptr) {
        errno = ENOSYS;
    }
    return function ? function(fd) : -1;
}

int ioctl(int fd, unsigned long request, void* arg)
{
    static auto* const function = next<int(int, unsigned long, ...)>("ioctl");
    if (function == nullptr) {
        errno = ENOSYS;
    }
    return function ? function(fd, request, arg) : -1;
}

void* mmap(void* address, size_t length, int protection, int flags, int fd, off_t offset)
{
    static auto* const function = next<void*(void*, size_t, int, int, int, off_t)>("mmap");
    if (function == nullptr) {
        errno = ENOSYS;
    }
    return function ? function(address, length, protection, flags, fd, offset) : MAP_FAILED;
}

void* mmap64(void* address, size_t length, int protection, int flags, int fd, off64_t offset)
{
    static auto* const function = next<void*(void*, size_t, int, int, int, off64_t)>("mmap64");
    if (function == nullptr) {
        errno = ENOSYS;
    }
    return function ? function(address, length, protection, flags, fd, offset) : MAP_FAILED;
}

int munmap(void* address, size_t length)
{
    static auto* const function = next<int(void*, size_t)>("munmap");
    if (function == nullptr) {
        errno = ENOSYS;
    }
    return function ? function(address, length) : -1;
}

int poll(pollfd* fds, nfds_t count, int timeoutMs)
{
    static auto* const function = next<int(pollfd*, nfds_t, int)>("poll");
    if (function == nullptr) {
        errno = ENOSYS;
    }
    return function ? function(fds, count, timeoutMs) : -1;
}

int select(int count, fd_set* readSet, fd_set* writeSet, fd_set* exceptSet, timeval* timeout)
{
    static auto* const function = next<int(int, fd_set*, fd_set*, fd_set*, timeval*)>("select");
    if (function == nullptr) {
        errno = ENOSYS;
    }
    return function ? function(count, readSet, writeSet, exceptSet, timeout) : -1;
}

int stat(const char* path, struct stat* out)
{
    static auto* const function = next<int(const char*, struct stat*)>("stat");
    if (function == nullptr) {
        errno = ENOSYS;
    }
    return function ? function(path, out) : -1;
}

int stat64(const char* path, struct stat64* out)
{
    static auto* const function = next<int(const char*, struct stat64*)>("stat64");
    if (function == nullptr) {
        errno = ENOSYS;
    }
    return function ? function(path, out) : -1;
}

FILE* fopen(const char* path, const char* mode)
{
    static auto* const function = next<FILE*(const char*, const char*)>("fopen");
    if (function == nullptr) {
        errno = ENOSYS;
    }
    return function ? function(path, mode) : nullptr;
}

FILE* fopen64(const char* path, const char* mode)
{
    static auto* const function = next<FILE*(const char*, const char*)>("fopen64");
    if (function == nullptr) {
        errno = ENOSYS;
    }
    return function ? function(path, mode) : nullptr;
}

} // namespace lumar::vcam::real
