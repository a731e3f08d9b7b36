// The configuration as `lumar check-config` reads it: parse and validate. Files the text
// names resolve against the shipped asset folder, so the seeds' models and maps load too.
#include "config/config.h"
#include "fuzz_support.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size)
{
    const std::filesystem::path baseDir = LUMAR_FUZZ_ASSET_DIR;
    (void)lumar::fuzz::scratchDir();
    return lumar::fuzz::expectInputErrorOnly([&] {
        (void)lumar::parseConfig(std::string_view(reinterpret_cast<const char*>(data), size), "fuzz.toml", baseDir);
    });
}
