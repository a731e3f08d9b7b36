#include "process_clock.h"

#include <ctime>
#include <fstream>
#include <sstream>
#include <string>

#include <unistd.h>

namespace lumar {

std::optional<double> millisecondsSinceProcessStart()
{
    std::ifstream file("/proc/self/stat");
    std::string stat;
    if (!std::getline(file, stat))
        return std::nullopt;
    // "pid (comm) state ppid ...": comm may hold spaces and parentheses, so count the fields
    // from the last ')'. starttime is field 22; state, field 3, is the first after it.
    const size_t close = stat.rfind(')');
    if (close == std::string::npos)
        return std::nullopt;
    std::istringstream fields(stat.substr(close + 1));
    std::string field;
    for (int i = 3; i < 22; ++i)
        fields >> field;
    unsigned long long startTicks = 0;
    if (!(fields >> startTicks))
        return std::nullopt;
    const long ticksPerSecond = ::sysconf(_SC_CLK_TCK);
    timespec now{};
    if (ticksPerSecond <= 0 || ::clock_gettime(CLOCK_BOOTTIME, &now) != 0)
        return std::nullopt;
    const double nowMs = double(now.tv_sec) * 1e3 + double(now.tv_nsec) * 1e-6;
    return nowMs - double(startTicks) * 1e3 / double(ticksPerSecond);
}

} // namespace lumar
