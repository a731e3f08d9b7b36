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

// What a camera stream is asked for, the same for V4L2 and libcamera (their options add what
// is their own: the device node and pixel format, the camera id and format name).
struct CameraStreamOptions {
    int width = 1280; // requested; the camera's closest size wins
    int height = 720;
    double fps = 30.0;         // requested; the camera may adjust it
    int bufferCount = 4;       // frame buffers asked for
    int frameTimeoutMs = 2000; // next() throws when no frame arrives for this long
    CameraControlsConfig controls;
    // NV12 and YUYV frames: true, deliver the planes as Frame::ycbcr (plus the tracker's
    // luma) and leave the RGB conversion to the renderer's GPU; false, convert to Frame::rgb
    // on the CPU.
    bool rawYcbcr = false;
    // With rawYcbcr: lend the camera's buffers (dmabufs for the renderer to import) to the
    // frames instead of copying the planes out; a lent buffer goes back to the camera when no
    // frame holds it. The sources ask for a few more buffers so the camera keeps enough.
    bool zeroCopy = false;
};

} // namespace lumar
