// The open virtual devices of this process, shared by the interposers (vcam_preload.cpp,
// vcam_epoll.cpp): each descriptor the C library handed out for the served path maps to its
// device and its file handle on it. One lock serialises every device call.
#pragma once

#include <cstdint>
#include <limits>
#include <map>
#include <memory>
#include <mutex>
#include <string>

#include <sys/epoll.h>

#include "vcam/virtual_device.h"

namespace lumar::vcam {

inline constexpr int64_t kForever = std::numeric_limits<int64_t>::max();

struct OpenDevice {
    std::shared_ptr<VirtualDevice> device;
    int handle = 0;
};

struct Registry {
    std::mutex mutex;
    std::map<int, OpenDevice> open;                             // by descriptor
    std::map<std::string, std::weak_ptr<VirtualDevice>> byPath; // opens of a path share its device
    // epoll instances watching devices: epoll descriptor → device descriptor → what it asked.
    std::map<int, std::map<int, epoll_event>> epollWatches;
};

// Never destroyed: interposers may run from other libraries' static destructors at exit.
Registry& registry();

int64_t nowNs();
// Milliseconds from now until `deadlineNs`, rounded up so a wake-up is never early (-1: forever).
int waitMsUntil(int64_t deadlineNs);

} // namespace lumar::vcam
