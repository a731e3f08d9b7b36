// A V4L2 capture device (a USB/CSI camera's /dev/videoN) behind the CaptureSource interface:
// single-planar MMAP streaming, NV12/YUYV/GREY converted on the CPU to sRGB plus luma.
// A failed device throws RuntimeError; reconnecting after an unplug is the caller's job.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <linux/videodev2.h>

#include "capture/capture_source.h"
#include "capture/v4l2/mapped_region.h"
#include "capture/v4l2/ycbcr_to_rgb.h"
#include "core/unique_fd.h"

namespace lumar {

struct V4l2Options {
    std::string device = "/dev/video0";
    int width = 1280; // requested; the device's closest size wins
    int height = 720;
    double fps = 30.0;         // requested frame rate (VIDIOC_S_PARM); the driver may adjust it
    int bufferCount = 4;       // MMAP buffers requested (at least 4 are used)
    int frameTimeoutMs = 2000; // next() throws when no frame arrives for this long
};

class V4l2Source final : public CaptureSource {
public:
    // Opens, negotiates and starts streaming. Throws RuntimeError when the device cannot be
    // opened, is not a streaming capture device, or offers no format lumar converts.
    explicit V4l2Source(V4l2Options options);
    ~V4l2Source() override;
    V4l2Source(const V4l2Source&) = delete;
    V4l2Source& operator=(const V4l2Source&) = delete;

    // Never returns false (a camera does not end); throws RuntimeError on timeout or unplug.
    bool next(Frame& frame) override;

    [[nodiscard]] int width() const override { return width_; }
    [[nodiscard]] int height() const override { return height_; }
    [[nodiscard]] double fps() const override { return fps_; }

    [[nodiscard]] uint32_t pixelFormat() const { return pixelFormat_; }
    [[nodiscard]] YCbCrColorimetry colorimetry() const { return converter_.colorimetry(); }
    [[nodiscard]] size_t bufferCount() const { return buffers_.size(); }
    // Frames the driver numbered but never delivered (sequence gaps).
    [[nodiscard]] uint64_t framesDropped() const { return framesDropped_; }
    // Frames delivered short (bytesused below the image size) or flagged as errors; skipped.
    [[nodiscard]] uint64_t framesCorrupt() const { return framesCorrupt_; }

private:
    void negotiateFormat();
    void requestFrameRate();
    void mapBuffers();
    void startStreaming();
    // Waits for and dequeues one buffer; returns false when it was corrupt (already requeued).
    bool dequeueGoodBuffer(v4l2_buffer& buffer);
    void queueBuffer(uint32_t index);
    void convert(const uint8_t* data, Frame& frame) const;

    V4l2Options options_;
    UniqueFd fd_;
    std::vector<MappedRegion> buffers_; // destroyed before fd_: unmapped before the close
    bool streaming_ = false;
    uint32_t pixelFormat_ = 0;
    int width_ = 0;
    int height_ = 0;
    double fps_ = 0.0;
    size_t bytesPerLine_ = 0;
    size_t imageSize_ = 0;
    YCbCrConverter converter_{YCbCrColorimetry{}};
    std::optional<uint32_t> lastSequence_;
    uint64_t framesDropped_ = 0;
    uint64_t framesCorrupt_ = 0;
};

} // namespace lumar
