// lumar check-config FILE: exit 0 when the file is a valid configuration or board profile
// (told apart by a top-level [board] table), else exit 2 with one line "FILE:LINE: what is
// wrong" on stderr.
#include <cstdio>

#include "command_line.h"
#include "commands.h"
#include "config/board_profile.h"
#include "config/config.h"
#include "core/error.h"

namespace lumar {

int checkConfigCommand(const Args& args)
{
    const CommandLine cl(args, {});
    if (cl.helpRequested()) {
        std::fputs("usage: lumar check-config FILE\n\nValidates FILE: syntax, keys, types, ranges and that "
                   "referenced files exist.\nA file with a [board] table is checked as a board profile "
                   "(board/README.md).\nPrints 'FILE: ok' and exits 0, or prints the first error as "
                   "FILE:LINE: message and exits 2.\n",
                   stdout);
        return kExitOk;
    }
    if (cl.positional().size() != 1)
        throw UsageError("expected exactly one FILE");
    const std::string& file = cl.positional().front();
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
