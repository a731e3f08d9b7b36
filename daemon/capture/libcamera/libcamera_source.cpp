#include "capture/libcamera/libcamera_source.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstring>
#include <sstream>

#include <libcamera/camera.h>
#include <libcamera/camera_manager.h>
#include <libcamera/control_ids.h>
#include <libcamera/formats.h>
#include <libcamera/framebuffer.h>
#include <libcamera/framebuffer_allocator.h>
#include <libcamera/request.h>
#include <libcamera/stream.h>
#include <time.h>

#include "capture/libcamera/libcamera_buffer.h"
#include "capture/libcamera/libcamera_controls.h"
#include "capture/libcamera/libcamera_frame.h"
#include "capture/libcamera/libcamera_manager.h"
#include "capture/reconnecting_source.h"
#include "core/error.h"
#include "core/log.h"

namespace lumar {
namespace {

// Corrupt frames are logged on the first and then every this many (a camera sending garbage
// all the time must not flood the journal).
constexpr uint64_t kCorruptLogEvery = 100;

int64_t monotonicNowNs()
{
    timespec now{};
    clock_gettime(CLOCK_MONOTONIC, &now);
    return int64_t(now.tv_sec) * 1'000'000'000 + now.tv_nsec;
}

std::string errorText(int negativeErrno)
{
    return std::strerror(-negativeErrno);
}

// "1280x720-NV12, 4 buffers": what a stream configuration asks for.
std::string describeStream(const libcamera::StreamConfiguration& stream)
{
    return stream.toString() + ", " + std::to_string(stream.bufferCount) + " buffers";
}

} // namespace

LibcameraSource::LibcameraSource(LibcameraOptions options) : options_(std::move(options))
{
    try {
        open();
    } catch (...) {
        // The destructor does not run for a half-built object: undo in libcamera's order here.
        shutdown();
        throw;
    }
}

void LibcameraSource::checkFormatName(const std::string& format)
{
    libcameraFormatFromName(format);
}

LibcameraSource::~LibcameraSource()
{
    shutdown();
}

void LibcameraSource::open()
{
    manager_ = acquireCameraManager();
    selectCamera();
    configureStream();
    allocateBuffers();
    start();
}

void LibcameraSource::selectCamera()
{
    const std::vector<std::shared_ptr<libcamera::Camera>> cameras = manager_->cameras();
    if (cameras.empty()) {
        throw CameraUnavailable(noLibcameraCamerasMessage());
    }
    for (const auto& camera : cameras) {
        if (camera->id() == options_.cameraId) {
            camera_ = camera;
        }
    }
    if (!camera_) {
        camera_ = cameras.front();
        LUMAR_LOG(Capture, Info) << "libcamera: camera.device '" << options_.cameraId
                                 << "' is no libcamera camera id; using the first camera";
    }
    cameraId_ = camera_->id();
    if (const int error = camera_->acquire(); error != 0) {
        throw CameraUnavailable("libcamera: camera " + cameraId_ + " cannot be acquired: " + errorText(error) +
                                (error == -EBUSY ? " (another process is using it)" : ""));
    }
    acquired_ = true;
    camera_->disconnected.connect(this, &LibcameraSource::onDisconnected);
}

void LibcameraSource::configureStream()
{
    configuration_ = camera_->generateConfiguration({libcamera::StreamRole::Viewfinder});
    if (!configuration_ || configuration_->empty()) {
        throw RuntimeError("libcamera: camera " + cameraId_ + " offers no viewfinder stream");
    }
    libcamera::StreamConfiguration& stream = configuration_->at(0);
    const libcamera::PixelFormat required = libcameraFormatFromName(options_.format);
    const libcamera::PixelFormat format = chooseLibcameraFormat(stream.formats().pixelformats(), required);
    if (!format.isValid()) {
        throw RuntimeError("libcamera: camera " + cameraId_ + " " +
                           noConvertibleFormatReason(stream.formats().pixelformats(), required));
    }
    stream.pixelFormat = format;
    stream.size = libcamera::Size(unsigned(std::max(options_.width, 1)), unsigned(std::max(options_.height, 1)));
    // Only YCbCr streams lend buffers; packed RGB is converted on the CPU whatever camera.convert says.
    const bool lends = options_.zeroCopy && options_.rawYcbcr && !isPackedRgbLibcameraFormat(format);
    stream.bufferCount = unsigned(std::max(options_.bufferCount, 2) + (lends ? kLentBuffers : 0));
    const std::string requested = describeStream(stream);
    switch (configuration_->validate()) {
    case libcamera::CameraConfiguration::Invalid:
        throw RuntimeError("libcamera: camera " + cameraId_ + " rejects the configuration " + requested);
    case libcamera::CameraConfiguration::Adjusted:
        // Size, format and buffer count are what validate() may change.
        LUMAR_LOG(Capture, Info) << "libcamera: " << cameraId_ << ": configuration adjusted from " << requested
                                 << " to " << describeStream(stream);
        break;
    case libcamera::CameraConfiguration::Valid:
        break;
    }
    if (const int error = camera_->configure(configuration_.get()); error != 0) {
        throw RuntimeError("libcamera: camera " + cameraId_ + " cannot be configured as " + stream.toString() + ": " +
                           errorText(error));
    }
    // validate() may have replaced the format or size; what it settled on is what we read.
    const LibcameraLayout layout{stream.pixelFormat, int(stream.size.width), int(stream.size.height), stream.stride};
    if (!isConvertibleLibcameraFormat(layout.format)) {
        throw RuntimeError("libcamera: camera " + cameraId_ + " replaced " + format.toString() + " by " +
                           layout.format.toString() + ", which lumar does not convert");
    }
    if (required.isValid() && layout.format != required) {
        LUMAR_LOG(Capture, Warn) << "libcamera: " << cameraId_ << ": camera.format " << required.toString()
                                 << " was replaced by " << layout.format.toString() << " when validated";
    }
    stream_ = stream.stream();
    width_ = layout.width;
    height_ = layout.height;
    stride_ = layout.stride;
    pixelFormat_ = layout.format.fourcc();
    const bool packedRgb = isPackedRgbLibcameraFormat(layout.format);
    gpuYcbcr_ = options_.rawYcbcr && !packedRgb;
    converter_ = YCbCrConverter(colorimetryOfColorSpace(stream.colorSpace));
    if (packedRgb) {
        // No YCbCr matrix or range applies: say only what the pipeline reported, if anything.
        LUMAR_LOG(Capture, Info) << "libcamera: " << cameraId_ << ": " << stream.toString() << ", packed RGB"
                                 << (stream.colorSpace
                                         ? ", colour space " + libcamera::ColorSpace::toString(stream.colorSpace)
                                         : std::string())
                                 << ", converted on the CPU";
        if (options_.rawYcbcr) {
            LUMAR_LOG(Capture, Info) << "libcamera: " << cameraId_ << ": camera.convert = \"gpu\" applies to "
                                     << "YCbCr streams only; this " << layout.format.toString()
                                     << " stream is converted on the CPU (and its buffers are not lent)";
        }
        return;
    }
    const YCbCrColorimetry colorimetry = converter_.colorimetry();
    LUMAR_LOG(Capture, Info) << "libcamera: " << cameraId_ << ": " << stream.toString() << ", colour space "
                             << libcamera::ColorSpace::toString(stream.colorSpace) << " ("
                             << (colorimetry.matrix == YCbCrMatrix::Bt709 ? "BT.709" : "BT.601")
                             << (colorimetry.fullRange ? " full range" : " limited range")
                             << (stream.colorSpace ? "" : ", assumed") << ")"
                             << (gpuYcbcr_ ? ", converted on the GPU" : "");
}

void LibcameraSource::allocateBuffers()
{
    allocator_ = std::make_unique<libcamera::FrameBufferAllocator>(camera_);
    const int allocated = allocator_->allocate(stream_);
    if (allocated < 0) {
        throw RuntimeError("libcamera: camera " + cameraId_ +
                           ": cannot allocate frame buffers: " + errorText(allocated));
    }
    const LibcameraLayout layout{libcamera::PixelFormat(pixelFormat_), width_, height_, stride_};
    for (const std::unique_ptr<libcamera::FrameBuffer>& buffer : allocator_->buffers(stream_)) {
        // Mapped once here, for the stream's life: no mmap per frame.
        DmabufMapping mapping(*buffer);
        if (const std::string problem = checkMappedImage(mapping, layout); !problem.empty()) {
            throw RuntimeError("libcamera: camera " + cameraId_ + ": unusable frame buffer: " + problem);
        }
        buffers_.emplace(buffer.get(), std::make_shared<LibcameraBuffer>(*buffer, std::move(mapping), layout));

        std::unique_ptr<libcamera::Request> request = camera_->createRequest();
        if (!request) {
            throw RuntimeError("libcamera: camera " + cameraId_ + ": cannot create a request");
        }
        if (const int error = request->addBuffer(stream_, buffer.get()); error != 0) {
            throw RuntimeError("libcamera: camera " + cameraId_ +
                               ": cannot attach a buffer to a request: " + errorText(error));
        }
        requests_.push_back(std::move(request));
    }
    if (requests_.size() < 2) {
        throw RuntimeError("libcamera: camera " + cameraId_ + ": " + std::to_string(requests_.size()) +
                           " frame buffer(s) allocated; streaming needs at least 2");
    }
}

void LibcameraSource::start()
{
    camera_->requestCompleted.connect(this, &LibcameraSource::onRequestCompleted);
    libcamera::ControlList controls(camera_->controls());
    fps_ = options_.fps;
    if (const auto duration = frameDurationFor(options_.fps, camera_->controls())) {
        // A fixed frame duration (minimum = maximum), in microseconds, within the camera's range.
        controls.set(libcamera::controls::FrameDurationLimits, libcamera::Span<const int64_t, 2>(*duration));
        fps_ = 1e6 / double((*duration)[0]);
        if (std::abs(fps_ - options_.fps) > 0.01) {
            LUMAR_LOG(Capture, Warn) << "libcamera: " << cameraId_ << ": " << options_.fps
                                     << " fps is outside the camera's frame duration range; " << fps_ << " fps";
        }
    } else if (options_.fps > 0.0) {
        LUMAR_LOG(Capture, Info) << "libcamera: " << cameraId_ << ": the camera has no FrameDurationLimits; "
                                 << "assuming " << fps_ << " fps";
    }
    addLibcameraControls(options_.controls, camera_->controls(), controls, cameraId_);
    if (const int error = camera_->start(&controls); error != 0) {
        throw RuntimeError("libcamera: camera " + cameraId_ + " fails to start: " + errorText(error));
    }
    started_ = true;
    for (const std::unique_ptr<libcamera::Request>& request : requests_) {
        if (const int error = camera_->queueRequest(request.get()); error != 0) {
            throw RuntimeError("libcamera: camera " + cameraId_ + ": cannot queue a request: " + errorText(error));
        }
    }
}

void LibcameraSource::shutdown() noexcept
{
    if (started_) {
        // Synchronous: pending requests complete (cancelled) before it returns, so no
        // completion can arrive after the disconnect below.
        camera_->stop();
        started_ = false;
    }
    if (camera_) {
        camera_->requestCompleted.disconnect(this);
        camera_->disconnected.disconnect(this);
    }
    completed_.clear();
    requests_.clear();
    lent_.clear();    // stopped: none of them is to be queued again
    buffers_.clear(); // unmapped, but for those frames still hold (they keep their own dmabufs)
    allocator_.reset();
    configuration_.reset();
    if (acquired_) {
        camera_->release();
        acquired_ = false;
    }
    camera_.reset();
    stream_ = nullptr;
    manager_.reset(); // last: stops the manager when no one else holds it
}

void LibcameraSource::onRequestCompleted(libcamera::Request* request)
{
    completed_.push(request);
}

void LibcameraSource::onDisconnected()
{
    completed_.disconnect();
}

libcamera::Request* LibcameraSource::waitForRequest(std::chrono::steady_clock::time_point deadline)
{
    libcamera::Request* request = nullptr;
    switch (completed_.waitUntil(deadline, request)) {
    case CompletionQueue<libcamera::Request*>::Wait::Disconnected:
        throw RuntimeError("libcamera: camera " + cameraId_ + " disconnected");
    case CompletionQueue<libcamera::Request*>::Wait::Timeout:
        return nullptr;
    case CompletionQueue<libcamera::Request*>::Wait::Item:
        break;
    }
    return request;
}

void LibcameraSource::requeue(libcamera::Request* request)
{
    request->reuse(libcamera::Request::ReuseBuffers);
    if (const int error = camera_->queueRequest(request); error != 0) {
        throw RuntimeError("libcamera: camera " + cameraId_ + ": cannot queue a request again: " + errorText(error));
    }
}

void LibcameraSource::returnLentBuffers()
{
    for (size_t i = 0; i < lent_.size();) {
        const std::shared_ptr<LibcameraBuffer>& buffer = *lent_[i].buffer;
        // The frames' handle has ended (acquire: their last reads happened before).
        if (buffer->returned()) {
            requeue(lent_[i].request);
            lent_[i] = lent_.back();
            lent_.pop_back();
        } else {
            ++i;
        }
    }
}

bool LibcameraSource::canLend() const
{
    // The request just completed, the lent ones, and at least two left with the camera.
    constexpr size_t kKeptQueued = 2;
    return options_.zeroCopy && gpuYcbcr_ && requests_.size() >= lent_.size() + 1 + kKeptQueued;
}

void LibcameraSource::lendBuffer(const std::shared_ptr<LibcameraBuffer>& buffer, const LibcameraLayout& layout,
                                 Frame& frame) const
{
    YCbCrImage& raw = frame.ycbcr;
    const bool nv12 = layout.format == libcamera::formats::NV12;
    raw.layout = nv12 ? YCbCrLayout::Nv12 : YCbCrLayout::Yuyv;
    raw.width = layout.width;
    raw.height = layout.height;
    raw.colorimetry = converter_.colorimetry();
    raw.plane0.clear();
    raw.plane1.clear();
    raw.stride0 = layout.stride;
    raw.stride1 = nv12 ? layout.stride : 0; // libcamera's NV12 chroma rows are as long as the luma rows
    // The frames' own handle (as V4l2Source::lendBuffer's): the end of its last copy gives the
    // buffer back, and it keeps the buffer's mapping alive for a frame that outlives us.
    buffer->lend();
    raw.buffer =
        std::shared_ptr<const CameraBuffer>(buffer.get(), [buffer](const CameraBuffer*) { buffer->giveBack(); });
    converter_.convertLuma(buffer->planes()[0].data, layout.stride, nv12 ? 1 : 2, layout.width, layout.height,
                           frame.luma);
}

bool LibcameraSource::next(Frame& frame)
{
    // The buffer this frame object showed last is free now (unless a copy of it lives on).
    frame.ycbcr.buffer.reset();
    returnLentBuffers();
    // One deadline for the whole call, so a camera sending only corrupt frames times out like
    // a silent one.
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::milliseconds(options_.frameTimeoutMs);
    const LibcameraLayout layout{libcamera::PixelFormat(pixelFormat_), width_, height_, stride_};
    const uint64_t corruptAtStart = framesCorrupt_;
    for (;;) {
        libcamera::Request* request = waitForRequest(deadline);
        if (request == nullptr) {
            std::ostringstream seconds;
            seconds << options_.frameTimeoutMs / 1000.0;
            throw RuntimeError("libcamera: camera " + cameraId_ + ": no frame for " + seconds.str() + " s" +
                               (framesCorrupt_ > corruptAtStart ? " (only corrupt ones)" : ""));
        }
        if (request->status() == libcamera::Request::RequestCancelled) {
            continue; // only while stopping; the request is not ours to queue again then
        }
        libcamera::FrameBuffer* buffer = request->findBuffer(stream_);
        const auto mapped = buffer != nullptr ? buffers_.find(buffer) : buffers_.end();
        if (mapped == buffers_.end()) {
            throw RuntimeError("libcamera: camera " + cameraId_ + " completed a request without our buffer");
        }
        const libcamera::FrameMetadata& metadata = buffer->metadata();
        if (lastSequence_ && metadata.sequence > *lastSequence_ + 1) {
            const uint32_t gap = metadata.sequence - *lastSequence_ - 1;
            framesDropped_ += gap;
            LUMAR_LOG(Capture, Warn) << "libcamera: " << cameraId_ << ": " << gap
                                     << " frame(s) dropped before sequence " << metadata.sequence << " ("
                                     << framesDropped_ << " in all)";
        }
        lastSequence_ = metadata.sequence;
        size_t bytesUsed = 0;
        for (const libcamera::FrameMetadata::Plane& plane : metadata.planes()) {
            bytesUsed += plane.bytesused;
        }
        if (metadata.status != libcamera::FrameMetadata::FrameSuccess || bytesUsed < imageBytes(layout)) {
            ++framesCorrupt_;
            if (framesCorrupt_ == 1 || framesCorrupt_ % kCorruptLogEvery == 0) {
                LUMAR_LOG(Capture, Warn) << "libcamera: " << cameraId_ << ": frame " << metadata.sequence
                                         << " is corrupt (" << bytesUsed << " of " << imageBytes(layout)
                                         << " bytes, status " << int(metadata.status) << "); skipped ("
                                         << framesCorrupt_ << " corrupt in all, logged every " << kCorruptLogEvery
                                         << ")";
            }
            requeue(request);
            continue;
        }
        const bool lend = canLend();
        if (lend) {
            lendBuffer(mapped->second, layout, frame);
        } else if (gpuYcbcr_) {
            keepLibcameraPlanes(mapped->second->mapping(), layout, converter_, frame);
        } else {
            // A frame object recycled from a raw frame must not carry stale planes.
            frame.ycbcr.layout = YCbCrLayout::None;
            convertLibcameraImage(mapped->second->mapping(), layout, converter_, frame);
        }
        frame.sequence = metadata.sequence;
        // The sensor's start-of-exposure time (CLOCK_MONOTONIC) where the pipeline reports it,
        // else the buffer's completion time, which is on the same clock.
        const std::optional<int64_t> sensorNs = request->metadata().get(libcamera::controls::SensorTimestamp);
        frame.timestampNs = sensorNs                  ? *sensorNs
                            : metadata.timestamp != 0 ? int64_t(metadata.timestamp)
                                                      : monotonicNowNs();
        frame.capturedNs = frame.timestampNs;
        if (lend) {
            lent_.push_back({request, &mapped->second}); // queued again once no frame holds it
        } else {
            requeue(request);
        }
        return true;
    }
}

} // namespace lumar
