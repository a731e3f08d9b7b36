// A Y4M clip played by `camera.source = "y4m"`: the header, then up to four frames (with
// looping, so the seek back is exercised).
#include "capture/y4m_source.h"
#include "config/config.h"
#include "core/frame.h"
#include "fuzz_support.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size)
{
    lumar::CameraConfig config;
    config.source = "y4m";
    config.path = lumar::fuzz::writeInput("clip.y4m", data, size);
    config.fps = 30.0;
    config.loop = true;
    return lumar::fuzz::expectInputErrorOnly([&] {
        lumar::Y4mSource source(config);
        lumar::Frame frame;
        for (int i = 0; i < 4 && source.next(frame); ++i) {
        }
    });
}
