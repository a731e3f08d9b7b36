// The capture stage's narrow interface (DESIGN.md §3). Implementations: the fake camera
// (synthetic tag scene), file playback (Y4M, image folder), V4L2 and libcamera cameras.
#pragma once

#include <memory>

#include "config/config.h"
#include "core/frame.h"

namespace lumar {

class CaptureSource {
public:
    virtual ~CaptureSource() = default;

    // Fills `frame` with the next frame, reusing its buffers. Returns false at the end of a
    // finite stream. Throws InputError for a corrupt file, RuntimeError for a device failure.
    virtual bool next(Frame& frame) = 0;

    [[nodiscard]] virtual int width() const = 0;
    [[nodiscard]] virtual int height() const = 0;
    [[nodiscard]] virtual double fps() const = 0;
};

// Opens the source the config names. Throws InputError for a bad path or file.
std::unique_ptr<CaptureSource> openCaptureSource(const CameraConfig& config);

} // namespace lumar
