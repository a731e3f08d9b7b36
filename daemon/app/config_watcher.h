// Notices when the configuration file is replaced or rewritten. Editors and `mv` replace a
// file by renaming a new one over it, which a watch on the file itself would lose, so the
// watch is on the file's directory, filtered by name (DESIGN.md §7).
#pragma once

#include <filesystem>
#include <string>

#include "core/unique_fd.h"

namespace lumar {

class ConfigWatcher {
public:
    // Throws RuntimeError when inotify is unavailable.
    explicit ConfigWatcher(const std::filesystem::path& file);

    // True when the file was written, created or renamed into place since the last call.
    // Never blocks.
    bool changed();

private:
    std::string name_;
    UniqueFd inotify_;
};

} // namespace lumar
