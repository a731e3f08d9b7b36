// Times one stage of a frame for RenderStats: wall-clock time, and the CPU time of the
// rendering threads (RenderCpuClock), which is the figure that survives a loaded machine.
#pragma once

#include <chrono>

#include "gles_renderer/gl/render_cpu_clock.h"
#include "gles_renderer/scene/scene_renderer.h"

namespace lumar {

class StageTimer {
public:
    // With `finish`, waits for the GPU at the start and on every split, so the time is the
    // stage's own (a GPU would otherwise overlap stages); without it the wall time is what
    // the calls took to queue. `cpu` may be null: no CPU time is taken.
    StageTimer(RenderCpuClock* cpu, bool finish);

    // The time since construction or the last split, added to `stage`; the next stage starts now.
    void split(StageTime& stage);

private:
    void start();

    RenderCpuClock* cpu_;
    bool finish_;
    std::chrono::steady_clock::time_point wall_;
    double cpuMs_ = 0.0;
};

} // namespace lumar
