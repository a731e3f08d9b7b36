#include "gles_renderer/scene/stage_timer.h"

#include <GLES3/gl3.h>

namespace lumar {

StageTimer::StageTimer(RenderCpuClock* cpu, bool finish) : cpu_(cpu), finish_(finish)
{
    if (finish_)
        glFinish();
    start();
}

void StageTimer::start()
{
    wall_ = std::chrono::steady_clock::now();
    if (cpu_)
        cpuMs_ = cpu_->nowMs();
}

void StageTimer::split(StageTime& stage)
{
    if (finish_)
        glFinish();
    stage.wallMs += std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - wall_).count();
    if (cpu_)
        stage.cpuMs += cpu_->nowMs() - cpuMs_;
    start();
}

} // namespace lumar
