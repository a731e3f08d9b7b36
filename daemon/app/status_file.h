// /run/lumar/status.json (path from [output] status_path): the daemon's state for other
// programs, rewritten atomically (write beside, rename over) so a reader never sees half a file.
#pragma once

#include <filesystem>
#include <string>
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
};

std::string statusJson(const RunStatus& status);

class StatusFile {
public:
    explicit StatusFile(std::filesystem::path path) : path_(std::move(path)) {}
    // Throws RuntimeError when the file cannot be written.
    void write(const RunStatus& status) const;
    [[nodiscard]] bool enabled() const { return !path_.empty(); }

private:
    std::filesystem::path path_;
};

} // namespace lumar
