// The LD_PRELOAD entry points: open/openat of the configured path open a file handle on the
// path's VirtualDevice (created by the first open, shared by later ones, gone with the last
// close) behind a real file descriptor (an eventfd, so close/fcntl behave); ioctl, mmap, poll
// and select on that descriptor go to the device, everything else to the C library.
// munmap needs no interposer: a buffer mapping is a plain mapping of the buffer's memfd.
#include <algorithm>
#include <cerrno>
#include <cstdarg>
#include <cstring>
#include <limits>
#include <map>
#include <memory>
#include <mutex>
#include <string_view>
#include <vector>

#include <fcntl.h>
#include <poll.h>
#include <sys/eventfd.h>
#include <sys/mman.h>
#include <sys/select.h>
#include <time.h>

#include "vcam/real_libc.h"
#include "vcam/vcam_registry.h"
#include "vcam/virtual_device.h"

namespace lumar::vcam {
namespace {

void sleepUntil(int64_t deadlineNs)
{
    timespec until{time_t(deadlineNs / 1'000'000'000), long(deadlineNs % 1'000'000'000)};
    while (clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &until, nullptr) == EINTR) {
    }
}

bool isServedPath(const char* path, Settings& settings)
{
    if (path == nullptr) {
        return false;
    }
    settings = settingsFromEnvironment();
    return std::string_view(path) == settings.devicePath;
}

int openDevice(Settings settings, int flags)
{
    const int fd = eventfd(0, ((flags & O_CLOEXEC) ? EFD_CLOEXEC : 0) | ((flags & O_NONBLOCK) ? EFD_NONBLOCK : 0));
    if (fd < 0) {
        return -1;
    }
    Registry& r = registry();
    const std::lock_guard lock(r.mutex);
    std::shared_ptr<VirtualDevice> device = r.byPath[settings.devicePath].lock();
    if (!device) {
        const std::string path = settings.devicePath;
        device = std::make_shared<VirtualDevice>(std::move(settings));
        r.byPath[path] = device;
    }
    r.open[fd] = OpenDevice{device, device->openHandle()};
    return fd;
}

mode_t modeArgument(int flags, va_list arguments)
{
    return (flags & (O_CREAT | O_TMPFILE)) ? mode_t(va_arg(arguments, unsigned)) : mode_t(0);
}

// Blocking or not is the descriptor's current state (fcntl may change it after open).
bool nonBlocking(int fd)
{
    const int flags = fcntl(fd, F_GETFL);
    return flags >= 0 && (flags & O_NONBLOCK) != 0;
}

int deviceIoctl(int fd, unsigned long request, void* arg, bool& served)
{
    Registry& r = registry();
    std::unique_lock lock(r.mutex);
    for (;;) {
        const auto found = r.open.find(fd);
        if (found == r.open.end()) {
            served = false;
            return 0;
        }
        served = true;
        const OpenDevice open = found->second;
        VirtualDevice& device = *open.device;
        const int error = device.ioctl(open.handle, request, arg, nowNs());
        // A blocking descriptor's DQBUF waits for the next frame, as a driver's does.
        if (error == EAGAIN && request == VIDIOC_DQBUF && !nonBlocking(fd) && device.streaming() &&
            device.nextFrameDueNs() != kForever) {
            const int64_t due = device.nextFrameDueNs();
            lock.unlock();
            sleepUntil(due);
            lock.lock();
            continue;
        }
        if (error != 0) {
            errno = error;
            return -1;
        }
        return 0;
    }
}

// poll() over a mix of virtual devices and real descriptors: the devices are answered here,
// the rest by the real poll() with the devices' entries disabled (fd -1), waiting no longer
// than the next frame falls due.
int pollWithDevices(pollfd* fds, nfds_t count, int timeoutMs)
{
    const int64_t deadline = timeoutMs < 0 ? kForever : nowNs() + int64_t(timeoutMs) * 1'000'000;
    std::vector<pollfd> others(fds, fds + count);
    for (;;) {
        int ready = 0;
        int64_t nextDue = kForever;
        bool anyDevice = false;
        {
            Registry& r = registry();
            const std::lock_guard lock(r.mutex);
            for (nfds_t i = 0; i < count; ++i) {
                const auto found = r.open.find(fds[i].fd);
                if (found == r.open.end()) {
                    continue;
                }
                anyDevice = true;
                others[i].fd = -1;
                VirtualDevice& device = *found->second.device;
                const short events = device.pollEvents(found->second.handle, fds[i].events, nowNs());
                fds[i].revents = short(events & (fds[i].events | POLLERR | POLLHUP | POLLNVAL));
                ready += fds[i].revents != 0 ? 1 : 0;
                nextDue = std::min(nextDue, device.nextFrameDueNs());
            }
        }
        if (!anyDevice) {
            return real::poll(fds, count, timeoutMs);
        }
        const int waitMs = ready > 0 ? 0 : waitMsUntil(std::min(deadline, nextDue));
        const int othersReady = real::poll(others.data(), count, waitMs);
        if (othersReady < 0) {
            return -1;
        }
        for (nfds_t i = 0; i < count; ++i) {
            if (others[i].fd >= 0) {
                fds[i].revents = others[i].revents;
            }
        }
        if (ready + othersReady > 0 || (deadline != kForever && nowNs() >= deadline)) {
            return ready + othersReady;
        }
    }
}

// select() likewise; POLLERR makes a descriptor readable, as the kernel's select does.
int selectWithDevices(int count, fd_set* readSet, fd_set* writeSet, fd_set* exceptSet, timeval* timeout)
{
    const int64_t deadline =
        timeout == nullptr ? kForever : nowNs() + int64_t(timeout->tv_sec) * 1'000'000'000 + timeout->tv_usec * 1000;
    const fd_set emptySet{};
    const fd_set readAsked = readSet ? *readSet : emptySet;
    const fd_set writeAsked = writeSet ? *writeSet : emptySet;
    const fd_set exceptAsked = exceptSet ? *exceptSet : emptySet;
    for (;;) {
        fd_set readOthers = readAsked;
        fd_set writeOthers = writeAsked;
        fd_set exceptOthers = exceptAsked;
        std::vector<int> readableDevices;
        std::vector<int> exceptionalDevices;
        int64_t nextDue = kForever;
        bool anyDevice = false;
        {
            Registry& r = registry();
            const std::lock_guard lock(r.mutex);
            for (const auto& [fd, open] : r.open) {
                if (fd >= count ||
                    !(FD_ISSET(fd, &readAsked) || FD_ISSET(fd, &exceptAsked) || FD_ISSET(fd, &writeAsked))) {
                    continue;
                }
                anyDevice = true;
                FD_CLR(fd, &readOthers);
                FD_CLR(fd, &writeOthers);
                FD_CLR(fd, &exceptOthers);
                VirtualDevice* device = open.device.get();
                const short requested = FD_ISSET(fd, &readAsked) ? short(POLLIN | POLLPRI) : short(POLLPRI);
                const short events = device->pollEvents(open.handle, requested, nowNs());
                if (FD_ISSET(fd, &readAsked) && (events & (POLLIN | POLLERR))) {
                    readableDevices.push_back(fd);
                }
                if (FD_ISSET(fd, &exceptAsked) && (events & POLLPRI)) {
                    exceptionalDevices.push_back(fd);
                }
                nextDue = std::min(nextDue, device->nextFrameDueNs());
            }
        }
        if (!anyDevice) {
            return real::select(count, readSet, writeSet, exceptSet, timeout);
        }
        const bool devicesReady = !readableDevices.empty() || !exceptionalDevices.empty();
        const int waitMs = devicesReady ? 0 : waitMsUntil(std::min(deadline, nextDue));
        timeval wait{};
        wait.tv_sec = waitMs / 1000;
        wait.tv_usec = (waitMs % 1000) * 1000;
        const int othersReady = real::select(count, readSet ? &readOthers : nullptr, writeSet ? &writeOthers : nullptr,
                                             exceptSet ? &exceptOthers : nullptr, waitMs < 0 ? nullptr : &wait);
        if (othersReady < 0) {
            return -1;
        }
        const int total = othersReady + int(readableDevices.size() + exceptionalDevices.size());
        if (total > 0 || (deadline != kForever && nowNs() >= deadline)) {
            for (int fd : readableDevices) {
                FD_SET(fd, &readOthers);
            }
            for (int fd : exceptionalDevices) {
                FD_SET(fd, &exceptOthers);
            }
            if (readSet)
                *readSet = readOthers;
            if (writeSet)
                *writeSet = writeOthers;
            if (exceptSet)
                *exceptSet = exceptOthers;
            return total;
        }
    }
}

bool anyDeviceOpen()
{
    Registry& r = registry();
    const std::lock_guard lock(r.mutex);
    return !r.open.empty();
}

} // namespace
} // namespace lumar::vcam

using namespace lumar::vcam;

extern "C" {

__attribute__((visibility("default"))) int open(const char* path, int flags, ...)
{
    va_list arguments;
    va_start(arguments, flags);
    const mode_t mode = modeArgument(flags, arguments);
    va_end(arguments);
    if (Settings settings; isServedPath(path, settings)) {
        return openDevice(std::move(settings), flags);
    }
    return real::open(path, flags, mode);
}

__attribute__((visibility("default"))) int open64(const char* path, int flags, ...)
{
    va_list arguments;
    va_start(arguments, flags);
    const mode_t mode = modeArgument(flags, arguments);
    va_end(arguments);
    if (Settings settings; isServedPath(path, settings)) {
        return openDevice(std::move(settings), flags);
    }
    return real::open64(path, flags, mode);
}

__attribute__((visibility("default"))) int openat(int directory, const char* path, int flags, ...)
{
    va_list arguments;
    va_start(arguments, flags);
    const mode_t mode = modeArgument(flags, arguments);
    va_end(arguments);
    if (Settings settings; isServedPath(path, settings)) {
        return openDevice(std::move(settings), flags);
    }
    return real::openat(directory, path, flags, mode);
}

__attribute__((visibility("default"))) int openat64(int directory, const char* path, int flags, ...)
{
    va_list arguments;
    va_start(arguments, flags);
    const mode_t mode = modeArgument(flags, arguments);
    va_end(arguments);
    if (Settings settings; isServedPath(path, settings)) {
        return openDevice(std::move(settings), flags);
    }
    return real::openat64(directory, path, flags, mode);
}

// The fortified entry points (_FORTIFY_SOURCE with non-constant flags, as in v4l-utils).
__attribute__((visibility("default"))) int __open_2(const char* path, int flags)
{
    if (Settings settings; isServedPath(path, settings)) {
        return openDevice(std::move(settings), flags);
    }
    return real::open(path, flags, 0);
}

__attribute__((visibility("default"))) int __open64_2(const char* path, int flags)
{
    if (Settings settings; isServedPath(path, settings)) {
        return openDevice(std::move(settings), flags);
    }
    return real::open64(path, flags, 0);
}

__attribute__((visibility("default"))) int __openat_2(int directory, const char* path, int flags)
{
    if (Settings settings; isServedPath(path, settings)) {
        return openDevice(std::move(settings), flags);
    }
    return real::openat(directory, path, flags, 0);
}

__attribute__((visibility("default"))) int close(int fd)
{
    {
        Registry& r = registry();
        const std::lock_guard lock(r.mutex);
        if (const auto found = r.open.find(fd); found != r.open.end()) {
            // The last handle's close destroys the device (its memfds; client mappings stay valid).
            found->second.device->closeHandle(found->second.handle);
            r.open.erase(found);
            for (auto& [epoll, watches] : r.epollWatches) {
                watches.erase(fd);
            }
        }
        r.epollWatches.erase(fd); // when fd was an epoll instance
    }
    return real::close(fd);
}

__attribute__((visibility("default"))) int ioctl(int fd, unsigned long request, ...)
{
    va_list arguments;
    va_start(arguments, request);
    void* arg = va_arg(arguments, void*);
    va_end(arguments);
    bool served = false;
    const int result = deviceIoctl(fd, request, arg, served);
    return served ? result : real::ioctl(fd, request, arg);
}

__attribute__((visibility("default"))) void* mmap(void* address, size_t length, int protection, int flags, int fd,
                                                  off_t offset) noexcept
{
    {
        Registry& r = registry();
        const std::lock_guard lock(r.mutex);
        if (const auto found = r.open.find(fd); found != r.open.end()) {
            int error = 0;
            const int memfd = found->second.device->memfdForMapping(length, offset, error);
            if (memfd < 0) {
                errno = error;
                return MAP_FAILED;
            }
            return real::mmap(address, length, protection, flags, memfd, 0); // each buffer has its own memfd
        }
    }
    return real::mmap(address, length, protection, flags, fd, offset);
}

__attribute__((visibility("default"))) void* mmap64(void* address, size_t length, int protection, int flags, int fd,
                                                    off64_t offset) noexcept
{
    return mmap(address, length, protection, flags, fd, off_t(offset));
}

__attribute__((visibility("default"))) int poll(pollfd* fds, nfds_t count, int timeoutMs)
{
    if (!anyDeviceOpen()) {
        return real::poll(fds, count, timeoutMs);
    }
    return pollWithDevices(fds, count, timeoutMs);
}

__attribute__((visibility("default"))) int select(int count, fd_set* readSet, fd_set* writeSet, fd_set* exceptSet,
                                                  timeval* timeout)
{
    if (!anyDeviceOpen()) {
        return real::select(count, readSet, writeSet, exceptSet, timeout);
    }
    return selectWithDevices(count, readSet, writeSet, exceptSet, timeout);
}

} // extern "C"
