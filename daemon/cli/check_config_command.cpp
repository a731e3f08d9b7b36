// lumar check-config FILE: exit 0 when the file is a valid configuration or board profile
// (told apart by a top-level [board] table), else exit 2 with one line "FILE:LINE: what is
// wrong" on stderr.
#include <cstdio>

#include "commands.h"
#include "config/board_profile.h"
#include "config/config.h"
#include "core/error.h"

namespace lumar {

int checkConfigCommand(const CheckConfigCommandOptions& options)
{
    const std::string& file = options.file;
    try {
        if (isBoardProfileFile(file))
            (void)loadBoardProfile(file);
        else
            (void)loadConfig(file);
    } catch (const InputError& e) {
        // Exactly one line, FILE:LINE: message, so editors and scripts can jump to it.
        std::fprintf(stderr, "%s\n", e.what());
        return kExitBadInput;
    }
    std::printf("%s: ok\n", file.c_str());
    return kExitOk;
}

} // namespace lumar
