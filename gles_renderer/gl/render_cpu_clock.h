// CPU time spent rendering: the calling thread's plus that of Mesa llvmpipe's rasteriser
// threads ("llvmpipe-0", ...). On a software rasteriser this is the rendering work itself,
// and unlike wall-clock time it hardly changes when other processes load the machine, so
// `lumar bench` reports it next to the wall times. On a GPU it is the driver's CPU time alone.
#pragma once

#include <ctime>
#include <vector>

namespace lumar {

class RenderCpuClock {
public:
    // Milliseconds of CPU time so far; differences between two calls are what counts. Call
    // after the GL context exists (llvmpipe starts its threads with the first context).
    [[nodiscard]] double nowMs();

private:
    void findRasteriserThreads();

    std::vector<clockid_t> threads_;
    bool searched_ = false;
};

} // namespace lumar
