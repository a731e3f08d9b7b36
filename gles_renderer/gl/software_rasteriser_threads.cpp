#include "gles_renderer/gl/software_rasteriser_threads.h"

#include <cstdlib>
#include <string>

#include <sched.h>

namespace lumar {

int chooseSoftwareRasteriserThreads()
{
    constexpr const char* kVariable = "LP_NUM_THREADS";
    if (const char* set = std::getenv(kVariable); set != nullptr && *set != '\0')
        return std::atoi(set);
    // The cores the scheduler lets us use (a cgroup's or taskset's), not all the machine has.
    cpu_set_t usable;
    CPU_ZERO(&usable);
    const int cores = sched_getaffinity(0, sizeof(usable), &usable) == 0 ? CPU_COUNT(&usable) : 1;
    // llvmpipe's default is one thread per core. One more keeps both cores busy where the
    // rasteriser would wait: while our thread bins the next pass and one of its threads has
    // a core, and at the end of a pass, whose last tiles go one to a thread. The car scene
    // replayed on llvmpipe, 2 cores (issue 18, three interleaved rounds): 29.5/31.2/32.2 ->
    // 31.8/32.5/33.4 fps without bloom, 27.9/28.2/28.8 -> 28.7/29.7/30.3 with it; the live fake
    // camera the same (23.8/24.2 against 23.6/23.5); peak resident memory the same. Later rounds
    // with bloom tied (28.8/27.7/29.5 against 29.6/29.7/28.5), and under foreign load the third
    // thread costs context switches (32.6k -> 52k per 200 frames): LP_NUM_THREADS overrides.
    const int threads = cores + 1;
    (void)setenv(kVariable, std::to_string(threads).c_str(), 0);
    return threads;
}

} // namespace lumar
