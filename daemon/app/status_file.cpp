#include "status_file.h"

#include <cerrno>
#include <cstring>
#include <fstream>

#include "core/error.h"
#include "core/json_output.h"
#include "core/log.h"

namespace lumar {

std::string statusJson(const RunStatus& s)
{
    const auto milliseconds = [](const std::optional<double>& ms) { return ms ? jsonDecimals(*ms, 1) : Json(nullptr); };
    const Json status = {
        {"state", "running"},
        {"fps", jsonDecimals(s.fps, 2)},
        {"frames", s.frames},
        {"frames_with_markers", s.framesWithMarkers},
        {"objects_drawn", s.objectsDrawn},
        {"uptime_s", jsonDecimals(s.uptimeS, 1)},
        {"startup_ms", milliseconds(s.startupMs)},
        {"last_reload_ms", milliseconds(s.lastReloadMs)},
        {"latency_ms", s.latencyP50Ms && s.latencyP99Ms
                           ? Json{{"p50", jsonDecimals(*s.latencyP50Ms, 1)}, {"p99", jsonDecimals(*s.latencyP99Ms, 1)}}
                           : Json(nullptr)},
        {"frames_dropped", s.framesDropped},
        {"markers_visible", s.markersVisible},
        {"camera", s.camera},
        {"config", s.config}};
    if (s.glObjects.empty())
        return jsonLine(status) + "\n";
    Json withGl = status;
    Json& counts = withGl["gl_objects"] = Json::object();
    for (const auto& [kind, alive] : s.glObjects)
        counts[kind] = alive;
    return jsonLine(withGl) + "\n";
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

bool StatusFile::writeOrReport(const RunStatus& status)
{
    try {
        write(status);
    } catch (const RuntimeError& e) {
        if (failure_ != e.what())
            LUMAR_LOG(Output, Error) << "status file not updated: " << e.what() << " (the daemon goes on)";
        failure_ = e.what();
        return false;
    }
    if (!failure_.empty())
        LUMAR_LOG(Output, Info) << path_.string() << ": status file written again";
    failure_.clear();
    return true;
}

} // namespace lumar
