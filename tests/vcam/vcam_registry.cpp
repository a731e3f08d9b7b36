#include "vcam/vcam_registry.h"

#include <algorithm>

#include <time.h>

namespace lumar::vcam {

Registry& registry()
{
    static auto* instance = new Registry;
    return *instance;
}

int64_t nowNs()
{
    timespec now{};
    clock_gettime(CLOCK_MONOTONIC, &now);
    return int64_t(now.tv_sec) * 1'000'000'000 + now.tv_nsec;
}

int waitMsUntil(int64_t deadlineNs)
{
    if (deadlineNs == kForever) {
        return -1;
    }
    const int64_t ms = (deadlineNs - nowNs() + 999'999) / 1'000'000;
    return int(std::clamp<int64_t>(ms, 0, std::numeric_limits<int>::max()));
}

} // namespace lumar::vcam
