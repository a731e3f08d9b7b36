// A material sidecar (MODEL.materials.toml), as an object's `materials` key loads it.
#include "config/material_sidecar.h"
#include "fuzz_support.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size)
{
    const std::filesystem::path file = lumar::fuzz::writeInput("model.materials.toml", data, size);
    return lumar::fuzz::expectInputErrorOnly([&] { (void)lumar::loadMaterialSidecar(file); });
}
