// The per-frame trace of `lumar render --trace FILE`: one JSON object per line with the
// frame's sequence, timestamps, raw detections (corners, pose) and map poses, the filtered
// poses the objects were placed with (and the objects' transforms as the renderer received
// them) and stage times, so tests and tools can compare what lumar saw and drew with ground
// truth without parsing logs.
#pragma once

#include <cstdio>
#include <filesystem>
#include <memory>

#include "pipeline.h"

namespace lumar {

class FrameTrace {
public:
    explicit FrameTrace(const std::filesystem::path& file); // throws RuntimeError
    void write(const FrameReport& report);

private:
    std::filesystem::path file_;
    std::unique_ptr<std::FILE, int (*)(std::FILE*)> out_;
};

} // namespace lumar
