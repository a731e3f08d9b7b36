// A glTF model, JSON or GLB (told apart by the GLB magic, as the loader does), with its
// buffers, images and accessors, through the loader objects and mesh phantoms use.
#include "fuzz_support.h"
#include "gles_renderer/assets/gltf_model.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size)
{
    const std::filesystem::path file = lumar::fuzz::writeInput("model.gltf", data, size);
    return lumar::fuzz::expectInputErrorOnly([&] { (void)lumar::loadGltfModel(file); });
}
