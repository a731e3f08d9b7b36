#include "status_file.h"

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <fstream>

#include "core/error.h"
#include "tracking/detection_json.h"

namespace lumar {

std::string statusJson(const RunStatus& s)
{
    std::string ids;
    for (int id : s.markersVisible)
        ids += (ids.empty() ? "" : ",") + std::to_string(id);
    char numbers[256];
    std::snprintf(numbers, sizeof numbers,
                  "\"fps\":%.2f,\"frames\":%ld,\"frames_with_markers\":%ld,\"objects_drawn\":%d,\"uptime_s\":%.1f",
                  s.fps, s.frames, s.framesWithMarkers, s.objectsDrawn, s.uptimeS);
    const auto milliseconds = [](const std::optional<double>& ms) {
        char text[32];
        std::snprintf(text, sizeof text, "%.1f", ms.value_or(0.0));
        return ms ? std::string(text) : std::string("null");
    };
    return std::string("{\"state\":\"running\",") + numbers + ",\"startup_ms\":" + milliseconds(s.startupMs) +
           ",\"last_reload_ms\":" + milliseconds(s.lastReloadMs) + ",\"markers_visible\":[" + ids +
           "],\"camera\":" + jsonString(s.camera) + ",\"config\":" + jsonString(s.config) + "}\n";
}

void StatusFile::write(const RunStatus& status) const
{
    if (path_.empty())
        return;
    const std::filesystem::path partial = path_.string() + ".partial";
    {
        std::ofstream out(partial, std::ios::trunc);
        out << statusJson(status);
        if (!out.flush())
            throw RuntimeError(partial.string() + ": cannot write: " + std::strerror(errno));
    }
    std::error_code ec;
    // Readable by every program that watches it, whatever the service's umask (the unit has
    // UMask=0077, which would leave the file to the service's dynamic user alone).
    namespace fs = std::filesystem;
    fs::permissions(partial,
                    fs::perms::owner_read | fs::perms::owner_write | fs::perms::group_read | fs::perms::others_read,
                    fs::perm_options::replace, ec);
    if (ec)
        throw RuntimeError(partial.string() + ": cannot set permissions: " + ec.message());
    fs::rename(partial, path_, ec);
    if (ec)
        throw RuntimeError(path_.string() + ": cannot replace: " + ec.message());
}

} // namespace lumar
