// A Radiance .hdr environment map, through the loader `[environment] hdr` uses.
#include "fuzz_support.h"
#include "gles_renderer/assets/environment_map.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size)
{
    const std::filesystem::path file = lumar::fuzz::writeInput("map.hdr", data, size);
    return lumar::fuzz::expectInputErrorOnly([&] { (void)lumar::loadHdrImage(file); });
}
