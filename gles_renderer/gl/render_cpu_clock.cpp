#include "gles_renderer/gl/render_cpu_clock.h"

#include <cstdlib>
#include <fstream>
#include <memory>
#include <string>

#include <dirent.h>
#include <sys/types.h>

namespace lumar {
namespace {

// The kernel's CPU clock of thread `tid` (CPUCLOCK_PERTHREAD | CPUCLOCK_SCHED, the encoding
// glibc's pthread_getcpuclockid uses): there is no pthread_t for a thread Mesa started.
clockid_t threadCpuClock(pid_t tid)
{
    return clockid_t((~unsigned(tid)) << 3) | 6;
}

double clockMs(clockid_t clock)
{
    timespec time{};
    if (clock_gettime(clock, &time) != 0)
        return 0.0; // the thread has ended: its time is lost, and so is its share of the difference
    return double(time.tv_sec) * 1e3 + double(time.tv_nsec) * 1e-6;
}

} // namespace

void RenderCpuClock::findRasteriserThreads()
{
    searched_ = true;
    const std::unique_ptr<DIR, int (*)(DIR*)> tasks(opendir("/proc/self/task"), closedir);
    if (!tasks)
        return;
    while (const dirent* entry = readdir(tasks.get())) {
        if (entry->d_name[0] == '.')
            continue;
        std::ifstream comm(std::string("/proc/self/task/") + entry->d_name + "/comm");
        std::string name;
        if (std::getline(comm, name) && name.starts_with("llvmpipe-"))
            threads_.push_back(threadCpuClock(pid_t(std::atoi(entry->d_name))));
    }
}

double RenderCpuClock::nowMs()
{
    if (!searched_)
        findRasteriserThreads();
    double total = clockMs(CLOCK_THREAD_CPUTIME_ID);
    for (const clockid_t thread : threads_)
        total += clockMs(thread);
    return total;
}

} // namespace lumar
