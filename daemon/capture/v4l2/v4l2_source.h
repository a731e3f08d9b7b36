// A V4L2 capture device (a USB/CSI camera's /dev/videoN) behind the CaptureSource interface:
// single-planar MMAP streaming, NV12/YUYV/GREY converted on the CPU to sRGB plus luma (or NV12
// and YUYV handed to the renderer: copied, or the buffers themselves lent as dmabufs), MJPEG
// decoded with libturbojpeg. Controls from the config are applied after the open. A
// V4L2_EVENT_SOURCE_CHANGE (the input's resolution changed) restarts the stream at the new
// size, or, when the caller cannot take a new size, is a RuntimeError.
// A failed device throws RuntimeError; reconnecting after an unplug is the caller's job.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <linux/videodev2.h>

#include "capture/capture_source.h"
#include "capture/v4l2/mjpeg_decoder.h"
#include "capture/v4l2/v4l2_buffer.h"
#include "capture/v4l2/v4l2_frame_layout.h"
#include "capture/v4l2/ycbcr_to_rgb.h"
#include "core/unique_fd.h"

namespace lumar {

// fps is asked for with VIDIOC_S_PARM; bufferCount MMAP buffers (at least 4 are used); MJPEG
// and GREY frames are always converted here, whatever rawYcbcr says; zero-copy buffers are
// exported once each as dmabufs (VIDIOC_EXPBUF) and kLentBuffers more are requested.
struct V4l2Options : CameraStreamOptions {
    std::string device = "/dev/video0";
    uint32_t pixelFormat = 0; // a fourcc the config requires; 0: the best the device offers
    // On a source change to another resolution: true, restart at the new size (width() and
    // height() follow, frames come at the new size); false, throw RuntimeError from next()
    // (for callers sized once at start, which reopen the camera instead).
    bool followResolutionChanges = true;
};

class V4l2Source final : public CaptureSource {
public:
    // Buffers a zero-copy stream asks for beyond bufferCount: the frames in flight between
    // capture and display (the prefetched one, the one on screen, the one the renderer holds
    // until the GPU is done with it).
    static constexpr int kLentBuffers = 3;

    // Opens, negotiates and starts streaming. Throws RuntimeError when the device cannot be
    // opened, is not a streaming capture device, or offers no format lumar converts.
    explicit V4l2Source(V4l2Options options);
    ~V4l2Source() override;
    V4l2Source(const V4l2Source&) = delete;
    V4l2Source& operator=(const V4l2Source&) = delete;

    // Never returns false (a camera does not end); throws RuntimeError on unplug, or when no
    // good frame (none at all, or only corrupt ones) arrives within the frame timeout.
    bool next(Frame& frame) override;

    [[nodiscard]] int width() const override { return width_; }
    [[nodiscard]] int height() const override { return height_; }
    [[nodiscard]] double fps() const override { return fps_; }

    [[nodiscard]] uint32_t pixelFormat() const { return pixelFormat_; }
    [[nodiscard]] YCbCrColorimetry colorimetry() const { return converter_.colorimetry(); }
    [[nodiscard]] size_t bufferCount() const { return buffers_.size(); }
    // Buffers frames hold now (zero-copy), and how many of the stream's buffers the driver
    // exported as dmabufs.
    [[nodiscard]] size_t buffersLent() const { return lent_.size(); }
    [[nodiscard]] size_t buffersExported() const { return exportedCount_; }
    // Frames the driver numbered but never delivered (sequence gaps).
    [[nodiscard]] uint64_t framesDropped() const { return framesDropped_; }
    // Frames delivered short (bytesused below the image size), flagged as errors, or (MJPEG)
    // that do not decode to the negotiated size; skipped.
    [[nodiscard]] uint64_t framesCorrupt() const { return framesCorrupt_; }
    // Source changes handled by restarting the stream (V4L2_EVENT_SOURCE_CHANGE).
    [[nodiscard]] int sourceChanges() const { return sourceChanges_; }
    // How long the last delivered frame took from its dequeued buffer to RGB + luma
    // (conversion or JPEG decode; with rawYcbcr, the plane copies and luma), for per-stage
    // timings.
    [[nodiscard]] int64_t lastConversionNs() const { return lastConversionNs_; }

private:
    void negotiateFormat();
    void requestFrameRate();
    void mapBuffers();
    void startStreaming();
    void subscribeToSourceChanges();
    // Dequeues pending events; a resolution change restarts the stream (or throws).
    void handleEvents();
    void restartAfterSourceChange();
    // Waits (until `deadlineNs` at most) for and dequeues one buffer; returns false when it was
    // corrupt (already requeued).
    bool dequeueGoodBuffer(v4l2_buffer& buffer, int64_t deadlineNs);
    void queueBuffer(uint32_t index);
    // Converts (or decodes) one buffer into the frame; false when the data is corrupt.
    bool convert(const uint8_t* data, size_t bytesUsed, Frame& frame);
    // The negotiated format's layout (v4l2_frame_layout.h).
    [[nodiscard]] V4l2FrameLayout layout() const;
    // Zero-copy: whether the buffer just dequeued can be lent (an NV12/YUYV stream asked to,
    // with at least two other buffers still with the driver), and lending it to the frame.
    [[nodiscard]] bool canLend() const;
    void lendBuffer(uint32_t index, Frame& frame);
    // Queues the lent buffers no frame holds any more.
    void returnLentBuffers();
    void countCorrupt(uint32_t sequence, const std::string& why);

    V4l2Options options_;
    UniqueFd fd_;
    // Each owns its mapping (and dmabuf); a lent one lives on in the frames that hold it,
    // even after this source is gone (a mapping outlives the close of the device).
    std::vector<std::shared_ptr<V4l2Buffer>> buffers_;
    std::vector<uint32_t> lent_; // indices of dequeued buffers that frames hold
    size_t exportedCount_ = 0;
    bool streaming_ = false;
    uint32_t pixelFormat_ = 0;
    int width_ = 0;
    int height_ = 0;
    double fps_ = 0.0;
    size_t bytesPerLine_ = 0;
    size_t imageSize_ = 0; // the bytes a raw frame needs; 0 for MJPEG (its size varies)
    bool subscribedToSourceChanges_ = false;
    int sourceChanges_ = 0;
    int64_t lastConversionNs_ = 0;
    std::unique_ptr<MjpegDecoder> mjpeg_; // while the format is MJPEG
    std::string decodeError_;
    YCbCrConverter converter_{YCbCrColorimetry{}};
    std::optional<uint32_t> lastSequence_;
    uint64_t framesDropped_ = 0;
    uint64_t framesCorrupt_ = 0;
    uint64_t corruptAtCallStart_ = 0;
};

} // namespace lumar
