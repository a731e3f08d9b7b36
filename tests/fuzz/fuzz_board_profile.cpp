// A board profile (board/*.toml), as lumar reads the file a config's `board` names.
#include "config/board_profile.h"
#include "fuzz_support.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size)
{
    const std::filesystem::path file = lumar::fuzz::writeInput("board.toml", data, size);
    return lumar::fuzz::expectInputErrorOnly([&] { (void)lumar::loadBoardProfile(file); });
}
