// epoll over virtual devices, which the kernel cannot see (their descriptors are idle
// eventfds): epoll_ctl on a device descriptor is remembered here instead of in the kernel, and
// epoll_wait on an instance that watches a device answers for the devices itself (level
// triggered, as V4L2 is) and waits in the kernel for the other descriptors no longer than
// the next frame falls due.
#include <algorithm>
#include <cerrno>
#include <mutex>

#include <dlfcn.h>
#include <poll.h>
#include <sys/epoll.h>

#include "vcam/vcam_registry.h"

namespace lumar::vcam {
namespace {

int realEpollCtl(int epoll, int operation, int fd, epoll_event* event)
{
    static auto* const function = reinterpret_cast<int (*)(int, int, int, epoll_event*)>(dlsym(RTLD_NEXT, "epoll_ctl"));
    if (function == nullptr) {
        errno = ENOSYS;
        return -1;
    }
    return function(epoll, operation, fd, event);
}

int realEpollWait(int epoll, epoll_event* events, int maxEvents, int timeoutMs)
{
    static auto* const function =
        reinterpret_cast<int (*)(int, epoll_event*, int, int)>(dlsym(RTLD_NEXT, "epoll_wait"));
    if (function == nullptr) {
        errno = ENOSYS;
        return -1;
    }
    return function(epoll, events, maxEvents, timeoutMs);
}

short toPoll(uint32_t epollEvents)
{
    return short(((epollEvents & EPOLLIN) ? POLLIN : 0) | ((epollEvents & EPOLLPRI) ? POLLPRI : 0) |
                 ((epollEvents & EPOLLRDNORM) ? POLLRDNORM : 0));
}

uint32_t toEpoll(short pollEvents)
{
    return ((pollEvents & POLLIN) ? uint32_t(EPOLLIN) : 0u) | ((pollEvents & POLLRDNORM) ? uint32_t(EPOLLRDNORM) : 0u) |
           ((pollEvents & POLLPRI) ? uint32_t(EPOLLPRI) : 0u) | ((pollEvents & POLLERR) ? uint32_t(EPOLLERR) : 0u) |
           ((pollEvents & POLLHUP) ? uint32_t(EPOLLHUP) : 0u);
}

} // namespace
} // namespace lumar::vcam

using namespace lumar::vcam;

extern "C" {

__attribute__((visibility("default"))) int epoll_ctl(int epoll, int operation, int fd, epoll_event* event)
{
    {
        Registry& r = registry();
        const std::lock_guard lock(r.mutex);
        if (r.open.count(fd) != 0) {
            auto& watches = r.epollWatches[epoll];
            const bool watched = watches.count(fd) != 0;
            switch (operation) {
            case EPOLL_CTL_ADD:
                if (watched) {
                    errno = EEXIST;
                    return -1;
                }
                watches[fd] = *event;
                return 0;
            case EPOLL_CTL_MOD:
                if (!watched) {
                    errno = ENOENT;
                    return -1;
                }
                watches[fd] = *event;
                return 0;
            case EPOLL_CTL_DEL:
                if (!watched) {
                    errno = ENOENT;
                    return -1;
                }
                watches.erase(fd);
                return 0;
            default:
                errno = EINVAL;
                return -1;
            }
        }
    }
    return realEpollCtl(epoll, operation, fd, event);
}

__attribute__((visibility("default"))) int epoll_wait(int epoll, epoll_event* events, int maxEvents, int timeoutMs)
{
    const int64_t deadline = timeoutMs < 0 ? kForever : nowNs() + int64_t(timeoutMs) * 1'000'000;
    for (;;) {
        int ready = 0;
        int64_t nextDue = kForever;
        {
            Registry& r = registry();
            const std::lock_guard lock(r.mutex);
            const auto found = r.epollWatches.find(epoll);
            if (found == r.epollWatches.end() || found->second.empty()) {
                break; // no device watched: the kernel alone answers
            }
            for (const auto& [fd, watch] : found->second) {
                const auto open = r.open.find(fd);
                if (open == r.open.end()) {
                    continue;
                }
                VirtualDevice& device = *open->second.device;
                const uint32_t happened =
                    toEpoll(device.pollEvents(open->second.handle, toPoll(watch.events), nowNs())) &
                    (watch.events | EPOLLERR | EPOLLHUP);
                nextDue = std::min(nextDue, device.nextFrameDueNs());
                if (happened != 0 && ready < maxEvents) {
                    events[ready].events = happened;
                    events[ready].data = watch.data;
                    ++ready;
                }
            }
        }
        const int waitMs = ready > 0 ? 0 : waitMsUntil(std::min(deadline, nextDue));
        const int others = ready < maxEvents ? realEpollWait(epoll, events + ready, maxEvents - ready, waitMs) : 0;
        if (others < 0) {
            return -1;
        }
        if (ready + others > 0 || (deadline != kForever && nowNs() >= deadline)) {
            return ready + others;
        }
    }
    return realEpollWait(epoll, events, maxEvents, timeoutMs);
}

} // extern "C"
