// /run/lumar/status.json (path from [output] status_path): the daemon's state for other
// programs, rewritten atomically (write beside, rename over) so a reader never sees half a file.
#pragma once

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace lumar {

struct RunStatus {
    double fps = 0.0;
    long frames = 0;
    long framesWithMarkers = 0;
    int objectsDrawn = 0;
    std::vector<int> markersVisible;
    std::string camera = "ok"; // or "unavailable: <reason>"
    std::string config = "ok"; // or "rejected: <FILE:LINE: message>"
    double uptimeS = 0.0;
    // Process creation to the first presented frame; the last accepted reload from its
    // trigger (signal or file event) to the new configuration applied. null until known.
    std::optional<double> startupMs;
    std::optional<double> lastReloadMs;
    // Capture-to-present latency over the latest frames (LatencyWindow); null until known.
    std::optional<double> latencyP50Ms;
    std::optional<double> latencyP99Ms;
    // Camera frames dropped for a newer one (capture/prefetching_source.h) since start-up.
    uint64_t framesDropped = 0;
    // Live GL objects per kind (gles_renderer/gl/gl_census.h), for the soak's leak check; left out
    // of the file while empty.
    std::vector<std::pair<std::string, int64_t>> glObjects;
};

std::string statusJson(const RunStatus& status);

class StatusFile {
public:
    explicit StatusFile(std::filesystem::path path) : path_(std::move(path)) {}
    // Throws RuntimeError when the file cannot be written.
    void write(const RunStatus& status) const;
    // What the running daemon calls: a status that cannot be written (disk full, directory
    // made read-only) is logged, not thrown, and the daemon goes on (issue 16's fault
    // campaign). One line when writing starts failing or fails for another reason, one when it
    // works again, not one a second. Returns whether the file was written.
    bool writeOrReport(const RunStatus& status);
    [[nodiscard]] bool enabled() const { return !path_.empty(); }

private:
    std::filesystem::path path_;
    std::string failure_; // the last write's error, empty while writes succeed
};

} // namespace lumar
