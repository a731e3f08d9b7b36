#include "frame_trace.h"

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <string>

#include "core/error.h"

namespace lumar {
namespace {

void appendf(std::string& s, const char* format, auto... values)
{
    char buffer[128];
    const int n = std::snprintf(buffer, sizeof buffer, format, values...);
    s.append(buffer, size_t(std::max(0, std::min(n, int(sizeof buffer) - 1))));
}

} // namespace

FrameTrace::FrameTrace(const std::filesystem::path& file)
    : file_(file), out_(std::fopen(file.c_str(), "w"), &std::fclose)
{
    if (!out_)
        throw RuntimeError(file.string() + ": cannot write: " + std::strerror(errno));
}

void FrameTrace::write(const FrameReport& r)
{
    std::string line;
    appendf(line, "{\"frame\":%llu,\"timestamp_ns\":%lld,\"objects_drawn\":%d,\"detections\":[",
            static_cast<unsigned long long>(r.sequence), static_cast<long long>(r.timestampNs), r.objectsDrawn);
    for (size_t i = 0; i < r.detections.size(); ++i) {
        const TagDetection& d = r.detections[i];
        appendf(line, "%s{\"id\":%d,\"corners\":[", i ? "," : "", d.id);
        for (int k = 0; k < 4; ++k)
            appendf(line, "%s[%.4f,%.4f]", k ? "," : "", d.corners[k].x, d.corners[k].y);
        line += "]";
        if (d.hasPose) {
            line += ",\"R\":[";
            for (int row = 0; row < 3; ++row)
                appendf(line, "%s[%.9g,%.9g,%.9g]", row ? "," : "", d.cameraFromMarker.R[0][row],
                        d.cameraFromMarker.R[1][row], d.cameraFromMarker.R[2][row]);
            appendf(line, "],\"t\":[%.9g,%.9g,%.9g]", d.cameraFromMarker.t.x, d.cameraFromMarker.t.y,
                    d.cameraFromMarker.t.z);
        }
        line += "}";
    }
    appendf(line, "],\"stage_ms\":{\"capture\":%.3f,\"detect\":%.3f,\"render\":%.3f,\"readback\":%.3f}}\n",
            r.times.captureMs, r.times.detectMs, r.times.renderMs, r.times.readbackMs);
    if (std::fwrite(line.data(), 1, line.size(), out_.get()) != line.size())
        throw RuntimeError(file_.string() + ": write failed: " + std::strerror(errno));
}

} // namespace lumar
