// A libcamera camera (a CSI sensor behind an ISP, or a UVC camera through libcamera's
// uvcvideo pipeline) behind the CaptureSource interface: one Viewfinder stream in NV12 (or
// YUYV), converted on the CPU to sRGB plus luma by the V4L2 backend's converter, or handed to
// the renderer as YCbCr planes (rawYcbcr): copied, or the frame buffers themselves lent
// (zeroCopy) for the renderer to import their dmabufs. Pipelines with no YCbCr viewfinder
// format (vimc) give packed RGB, which is always converted on the CPU. Controls from the
// config go with start(). Requests complete on libcamera's thread into a queue next() waits on; the completed
// buffer is read through a dmabuf mapping made once per buffer, and its request is queued
// again (a lent one once no frame holds its buffer).
// A failed or missing camera throws CameraUnavailable (a RuntimeError); reconnecting after an
// unplug is the caller's job (ReconnectingSource).
#pragma once

#include <chrono>
#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "capture/capture_source.h"
#include "capture/libcamera/completion_queue.h"
#include "capture/v4l2/ycbcr_to_rgb.h"

namespace libcamera {
class Camera;
class CameraConfiguration;
class CameraManager;
class FrameBuffer;
class FrameBufferAllocator;
class Request;
class Stream;
} // namespace libcamera

namespace lumar {

class LibcameraBuffer;
struct LibcameraLayout;

// fps is asked for through FrameDurationLimits where the camera has it; bufferCount frame
// buffers (and requests); a lent buffer's request is queued again when no frame holds it.
struct LibcameraOptions : CameraStreamOptions {
    // A libcamera camera id (as `lumar probe` lists them); anything else, such as the
    // config's default "/dev/video0", selects the first camera.
    std::string cameraId;
    // camera.format: "auto" (NV12, then YUYV, then packed RGB), "nv12" or "yuyv".
    std::string format = "auto";
};

class LibcameraSource final : public CaptureSource {
public:
    // Frame buffers a zero-copy stream asks for beyond bufferCount (see V4l2Source).
    static constexpr int kLentBuffers = 3;

    // Picks, configures and starts the camera. Throws CameraUnavailable when libcamera finds
    // no camera (or none by that id is free), RuntimeError when the camera cannot be
    // configured in a format lumar converts or fails to start.
    explicit LibcameraSource(LibcameraOptions options);
    // Throws InputError when camera.format names a format libcamera cameras are not read in.
    static void checkFormatName(const std::string& format);
    ~LibcameraSource() override;
    LibcameraSource(const LibcameraSource&) = delete;
    LibcameraSource& operator=(const LibcameraSource&) = delete;

    // Never returns false; throws RuntimeError when the camera disconnects, a request cannot
    // be queued again, or no good frame arrives within the frame timeout.
    bool next(Frame& frame) override;

    [[nodiscard]] int width() const override { return width_; }
    [[nodiscard]] int height() const override { return height_; }
    [[nodiscard]] double fps() const override { return fps_; }

    [[nodiscard]] const std::string& cameraId() const { return cameraId_; }
    [[nodiscard]] YCbCrColorimetry colorimetry() const { return converter_.colorimetry(); }
    // Frames the pipeline numbered but never delivered (sequence gaps).
    [[nodiscard]] uint64_t framesDropped() const { return framesDropped_; }
    // Frames completed with an error status or short of a whole image; skipped.
    [[nodiscard]] uint64_t framesCorrupt() const { return framesCorrupt_; }

private:
    void open();
    void selectCamera();
    void configureStream();
    void allocateBuffers();
    void start();
    // Idempotent; releases everything in the order libcamera requires (stop, requests,
    // buffers, configuration, camera, manager). The destructor and a failed open() use it.
    void shutdown() noexcept;
    // Called on libcamera's thread.
    void onRequestCompleted(libcamera::Request* request);
    void onDisconnected();
    // Waits until `deadline` at most; nullptr on timeout. Throws when the camera is gone.
    libcamera::Request* waitForRequest(std::chrono::steady_clock::time_point deadline);
    void requeue(libcamera::Request* request);
    // Zero-copy (as V4l2Source): whether the completed buffer can be lent, lending it, and
    // queueing the requests of lent buffers no frame holds any more.
    [[nodiscard]] bool canLend() const;
    void lendBuffer(const std::shared_ptr<LibcameraBuffer>& buffer, const LibcameraLayout& layout, Frame& frame) const;
    void returnLentBuffers();

    LibcameraOptions options_;
    std::shared_ptr<libcamera::CameraManager> manager_;
    std::shared_ptr<libcamera::Camera> camera_;
    std::string cameraId_;
    bool acquired_ = false;
    bool started_ = false;
    std::unique_ptr<libcamera::CameraConfiguration> configuration_;
    libcamera::Stream* stream_ = nullptr;
    std::unique_ptr<libcamera::FrameBufferAllocator> allocator_;
    // Each owns its mapping and dmabufs; a lent one lives on in the frames that hold it.
    std::map<const libcamera::FrameBuffer*, std::shared_ptr<LibcameraBuffer>> buffers_;
    struct Lent {
        libcamera::Request* request;
        const std::shared_ptr<LibcameraBuffer>* buffer; // its entry in buffers_
    };
    std::vector<Lent> lent_; // completed requests whose buffers frames hold
    std::vector<std::unique_ptr<libcamera::Request>> requests_;

    int width_ = 0;
    int height_ = 0;
    double fps_ = 0.0;
    size_t stride_ = 0;
    uint32_t pixelFormat_ = 0; // the stream's fourcc
    // rawYcbcr and a YCbCr stream: frames keep (or lend) the planes for the GPU. False for
    // packed RGB, which has no planes the renderer's YCbCr conversion takes.
    bool gpuYcbcr_ = false;
    YCbCrConverter converter_{YCbCrColorimetry{}};

    // Filled on libcamera's thread, drained by next().
    CompletionQueue<libcamera::Request*> completed_;

    std::optional<uint32_t> lastSequence_;
    uint64_t framesDropped_ = 0;
    uint64_t framesCorrupt_ = 0;
};

} // namespace lumar
