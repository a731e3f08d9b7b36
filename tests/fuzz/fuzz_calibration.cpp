// A camera calibration file, as `lumar detect --calib` and `camera.calibration` load it.
#include "fuzz_support.h"
#include "tracking/calibration_io.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size)
{
    const std::filesystem::path file = lumar::fuzz::writeInput("camera.yaml", data, size);
    return lumar::fuzz::expectInputErrorOnly([&] { (void)lumar::loadCalibration(file); });
}
