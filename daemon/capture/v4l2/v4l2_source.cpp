#include "capture/v4l2/v4l2_source.h"

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstring>
#include <sstream>

#include <fcntl.h>
#include <linux/videodev2.h>
#include <poll.h>
#include <sys/mman.h>
#include <time.h>

#include "capture/v4l2/v4l2_controls.h"
#include "capture/v4l2/v4l2_format.h"
#include "capture/v4l2/v4l2_frame_layout.h"
#include "capture/v4l2/v4l2_ioctl.h"
#include "core/error.h"
#include "core/log.h"

namespace lumar {
namespace {

constexpr int kMinimumBuffers = 4;
// Corrupt frames are logged on the first and then every this many, so a camera that sends
// garbage all the time cannot flood the journal.
constexpr uint64_t kCorruptLogEvery = 100;

int64_t monotonicNowNs()
{
    timespec now{};
    clock_gettime(CLOCK_MONOTONIC, &now);
    return int64_t(now.tv_sec) * 1'000'000'000 + now.tv_nsec;
}

std::string secondsText(int milliseconds)
{
    std::ostringstream text;
    text << milliseconds / 1000.0;
    return text.str();
}

} // namespace

V4l2Source::V4l2Source(V4l2Options options) : options_(std::move(options))
{
    const std::string& device = options_.device;
    // Non-blocking, so a wedged driver can only stall us for the poll() timeout.
    fd_ = UniqueFd(::open(device.c_str(), O_RDWR | O_NONBLOCK | O_CLOEXEC));
    if (!fd_.valid()) {
        throw RuntimeError(device + ": cannot open: " + std::strerror(errno));
    }

    v4l2_capability capability{};
    v4l2IoctlOrThrow(device, fd_.get(), VIDIOC_QUERYCAP, &capability, "VIDIOC_QUERYCAP (not a V4L2 device?)");
    const uint32_t caps =
        (capability.capabilities & V4L2_CAP_DEVICE_CAPS) ? capability.device_caps : capability.capabilities;
    if (!(caps & V4L2_CAP_VIDEO_CAPTURE) || !(caps & V4L2_CAP_STREAMING)) {
        throw RuntimeError(device + ": not a streaming video capture device (single-planar capture and "
                                    "streaming I/O are required)");
    }
    LUMAR_LOG(Capture, Info) << device << ": " << reinterpret_cast<const char*>(capability.card) << " ("
                             << reinterpret_cast<const char*>(capability.driver) << ")";

    negotiateFormat();
    requestFrameRate();
    if (!options_.controls.empty()) {
        applyCameraControls(device, fd_.get(), options_.controls);
    }
    mapBuffers();
    subscribeToSourceChanges();
    startStreaming();
}

V4l2Source::~V4l2Source()
{
    if (streaming_) {
        int type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
        // An unplugged device fails here with ENODEV; there is nothing left to stop then.
        v4l2Ioctl(fd_.get(), VIDIOC_STREAMOFF, &type);
    }
}

void V4l2Source::negotiateFormat()
{
    const std::string& device = options_.device;
    const std::vector<uint32_t> formats = enumeratePixelFormats(device, fd_.get());
    pixelFormat_ = choosePixelFormat(formats, options_.pixelFormat);
    if (pixelFormat_ == 0) {
        std::string offered;
        for (uint32_t f : formats) {
            offered += (offered.empty() ? "" : ", ") + fourccName(f);
        }
        throw RuntimeError(
            device + ": " +
            (options_.pixelFormat != 0 ? "camera.format " + fourccName(options_.pixelFormat) + " is not offered"
                                       : std::string("no supported pixel format")) +
            " (offers " + (offered.empty() ? "none" : offered) + "; lumar converts NV12, YUYV, MJPEG, GREY)");
    }
    const FrameSize requested{uint32_t(std::max(options_.width, 1)), uint32_t(std::max(options_.height, 1))};
    const FrameSize size = chooseFrameSize(enumerateFrameSizes(device, fd_.get(), pixelFormat_, requested), requested);

    v4l2_format format{};
    format.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
    format.fmt.pix.width = size.width;
    format.fmt.pix.height = size.height;
    format.fmt.pix.pixelformat = pixelFormat_;
    format.fmt.pix.field = V4L2_FIELD_NONE;
    v4l2IoctlOrThrow(device, fd_.get(), VIDIOC_S_FMT, &format, "VIDIOC_S_FMT");
    const v4l2_pix_format& accepted = format.fmt.pix;
    const V4l2FrameLayout layout = frameLayoutOf(device, accepted, pixelFormat_);
    width_ = layout.width;
    height_ = layout.height;
    bytesPerLine_ = layout.bytesPerLine;
    imageSize_ = layout.imageSize;
    const bool compressed = pixelFormat_ == V4L2_PIX_FMT_MJPEG;
    if (compressed && !mjpeg_) {
        mjpeg_ = std::make_unique<MjpegDecoder>();
    }
    converter_ = YCbCrConverter(colorimetryOf(accepted));
    if (compressed) {
        // JFIF: BT.601 full range whatever the driver says; libturbojpeg decodes it so.
        LUMAR_LOG(Capture, Info) << device << ": MJPEG " << width_ << "x" << height_ << " (up to " << accepted.sizeimage
                                 << " bytes a frame)";
        return;
    }
    LUMAR_LOG(Capture, Info) << device << ": " << fourccName(pixelFormat_) << " " << width_ << "x" << height_
                             << (converter_.colorimetry().matrix == YCbCrMatrix::Bt709 ? " BT.709" : " BT.601")
                             << (converter_.colorimetry().fullRange ? " full range" : " limited range")
                             << (options_.rawYcbcr && pixelFormat_ != V4L2_PIX_FMT_GREY ? ", converted on the GPU"
                                                                                        : "");
}

void V4l2Source::requestFrameRate()
{
    fps_ = options_.fps;
    v4l2_streamparm parameters{};
    parameters.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
    if (v4l2Ioctl(fd_.get(), VIDIOC_G_PARM, &parameters) != 0 ||
        !(parameters.parm.capture.capability & V4L2_CAP_TIMEPERFRAME)) {
        LUMAR_LOG(Capture, Info) << options_.device << ": frame rate not settable; assuming " << fps_ << " fps";
        return;
    }
    if (options_.fps > 0.0) {
        // fps as a fraction with a millisecond-resolution denominator: 30 → 1000/30000.
        parameters.parm.capture.timeperframe.numerator = 1000;
        parameters.parm.capture.timeperframe.denominator = uint32_t(std::lround(options_.fps * 1000.0));
        v4l2IoctlOrThrow(options_.device, fd_.get(), VIDIOC_S_PARM, &parameters, "VIDIOC_S_PARM");
    }
    const auto& interval = parameters.parm.capture.timeperframe;
    if (interval.numerator > 0 && interval.denominator > 0) {
        fps_ = double(interval.denominator) / double(interval.numerator);
    }
}

void V4l2Source::mapBuffers()
{
    const std::string& device = options_.device;
    v4l2_requestbuffers request{};
    const bool lending = options_.zeroCopy && options_.rawYcbcr &&
                         (pixelFormat_ == V4L2_PIX_FMT_NV12 || pixelFormat_ == V4L2_PIX_FMT_YUYV);
    request.count = uint32_t(std::max(options_.bufferCount, kMinimumBuffers) + (lending ? kLentBuffers : 0));
    request.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
    request.memory = V4L2_MEMORY_MMAP;
    v4l2IoctlOrThrow(device, fd_.get(), VIDIOC_REQBUFS, &request, "VIDIOC_REQBUFS (MMAP)");
    if (request.count < 2) {
        throw RuntimeError(device + ": the driver granted " + std::to_string(request.count) +
                           " buffers; streaming needs at least 2");
    }
    if (request.count < uint32_t(kMinimumBuffers)) {
        LUMAR_LOG(Capture, Warn) << device << ": only " << request.count << " buffers granted; frames may drop";
    }
    buffers_.reserve(request.count);
    exportedCount_ = 0;
    std::string exportError; // the first failure; the driver will not export the others either
    for (uint32_t index = 0; index < request.count; ++index) {
        v4l2_buffer buffer{};
        buffer.index = index;
        buffer.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
        buffer.memory = V4L2_MEMORY_MMAP;
        v4l2IoctlOrThrow(device, fd_.get(), VIDIOC_QUERYBUF, &buffer, "VIDIOC_QUERYBUF");
        if (buffer.length < imageSize_) {
            throw RuntimeError(device + ": buffer " + std::to_string(index) + " holds " +
                               std::to_string(buffer.length) + " bytes, the image needs " + std::to_string(imageSize_));
        }
        void* address =
            ::mmap(nullptr, buffer.length, PROT_READ | PROT_WRITE, MAP_SHARED, fd_.get(), off_t(buffer.m.offset));
        if (address == MAP_FAILED) {
            throwDeviceError(device, "mmap of a capture buffer", errno);
        }
        MappedRegion mapping(address, buffer.length);
        // Exported once for the stream's life: the renderer imports each buffer once too.
        UniqueFd dmabuf;
        if (lending && exportError.empty()) {
            dmabuf = exportV4l2Buffer(fd_.get(), index, exportError);
        }
        exportedCount_ += dmabuf.valid() ? 1 : 0;
        buffers_.push_back(
            std::make_shared<V4l2Buffer>(std::move(mapping), std::move(dmabuf), pixelFormat_, height_, bytesPerLine_));
    }
    if (lending) {
        LUMAR_LOG(Capture, Info) << device << ": " << buffers_.size() << " buffers lent to the renderer (zero-copy), "
                                 << (exportError.empty() ? "exported as dmabufs"
                                                         : "not exported (" + exportError + "): uploaded from memory");
    }
}

void V4l2Source::startStreaming()
{
    for (uint32_t index = 0; index < buffers_.size(); ++index) {
        queueBuffer(index);
    }
    int type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
    v4l2IoctlOrThrow(options_.device, fd_.get(), VIDIOC_STREAMON, &type, "VIDIOC_STREAMON");
    streaming_ = true;
}

void V4l2Source::subscribeToSourceChanges()
{
    v4l2_event_subscription subscription{};
    subscription.type = V4L2_EVENT_SOURCE_CHANGE;
    subscription.id = 0; // the input
    // Most cameras have no source-change events (ENOTTY/EINVAL): nothing to watch then.
    subscribedToSourceChanges_ = v4l2Ioctl(fd_.get(), VIDIOC_SUBSCRIBE_EVENT, &subscription) == 0;
}

void V4l2Source::handleEvents()
{
    bool resolutionChanged = false;
    for (;;) {
        v4l2_event event{};
        const int error = v4l2Ioctl(fd_.get(), VIDIOC_DQEVENT, &event);
        if (error == ENOENT) {
            break; // no more pending
        }
        if (error != 0) {
            throwDeviceError(options_.device, "VIDIOC_DQEVENT", error);
        }
        if (event.type == V4L2_EVENT_SOURCE_CHANGE && (event.u.src_change.changes & V4L2_EVENT_SRC_CH_RESOLUTION)) {
            resolutionChanged = true;
        }
    }
    if (resolutionChanged) {
        restartAfterSourceChange();
    }
}

void V4l2Source::restartAfterSourceChange()
{
    const std::string& device = options_.device;
    const int oldWidth = width_;
    const int oldHeight = height_;
    int type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
    v4l2IoctlOrThrow(device, fd_.get(), VIDIOC_STREAMOFF, &type, "VIDIOC_STREAMOFF");
    streaming_ = false;
    buffers_.clear(); // unmapped before the buffers are freed, but for those frames still hold
    lent_.clear();    // they are not the new stream's to queue
    v4l2_requestbuffers release{};
    release.count = 0;
    release.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
    release.memory = V4L2_MEMORY_MMAP;
    v4l2IoctlOrThrow(device, fd_.get(), VIDIOC_REQBUFS, &release, "VIDIOC_REQBUFS (release)");
    // The requested size again: the device now offers the new input's size.
    negotiateFormat();
    const std::string change = std::to_string(oldWidth) + "x" + std::to_string(oldHeight) + " to " +
                               std::to_string(width_) + "x" + std::to_string(height_);
    if (!options_.followResolutionChanges && (width_ != oldWidth || height_ != oldHeight)) {
        throw RuntimeError(device + ": the source changed resolution from " + change +
                           "; the capture size is fixed at start, so the camera is reopened");
    }
    requestFrameRate();
    mapBuffers();
    startStreaming();
    lastSequence_.reset(); // the driver numbers the new stream from 0
    ++sourceChanges_;
    LUMAR_LOG(Capture, Info) << device << ": source changed from " << change << "; streaming again";
}

void V4l2Source::queueBuffer(uint32_t index)
{
    v4l2_buffer buffer{};
    buffer.index = index;
    buffer.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
    buffer.memory = V4L2_MEMORY_MMAP;
    v4l2IoctlOrThrow(options_.device, fd_.get(), VIDIOC_QBUF, &buffer, "VIDIOC_QBUF");
}

bool V4l2Source::dequeueGoodBuffer(v4l2_buffer& buffer, int64_t deadline)
{
    const std::string& device = options_.device;
    for (;;) {
        // With source-change events subscribed, look for one before each dequeue: a driver
        // may keep delivering frames of the old size after announcing the change.
        if (subscribedToSourceChanges_) {
            pollfd check{fd_.get(), POLLPRI, 0};
            if (::poll(&check, 1, 0) > 0 && (check.revents & POLLPRI)) {
                handleEvents();
            }
        }
        buffer = v4l2_buffer{};
        buffer.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
        buffer.memory = V4L2_MEMORY_MMAP;
        const int error = v4l2Ioctl(fd_.get(), VIDIOC_DQBUF, &buffer);
        if (error == 0) {
            break;
        }
        if (error != EAGAIN) {
            throwDeviceError(device, "VIDIOC_DQBUF", error);
        }
        const int64_t remainingMs = (deadline - monotonicNowNs() + 999'999) / 1'000'000;
        if (remainingMs <= 0) {
            throw RuntimeError(device + ": no frame for " + secondsText(options_.frameTimeoutMs) + " s" +
                               (framesCorrupt_ > corruptAtCallStart_ ? " (only corrupt ones)" : ""));
        }
        pollfd waitFor{fd_.get(), short(POLLIN | (subscribedToSourceChanges_ ? POLLPRI : 0)), 0};
        const int ready = ::poll(&waitFor, 1, int(remainingMs));
        if (ready < 0 && errno != EINTR) {
            throwDeviceError(device, "poll", errno);
        }
        // POLLPRI: an event, handled at the top; POLLERR: the next DQBUF reports the cause
        // (ENODEV for an unplugged device).
    }
    if (buffer.index >= buffers_.size()) {
        throw RuntimeError(device + ": the driver returned buffer index " + std::to_string(buffer.index) + " of " +
                           std::to_string(buffers_.size()));
    }
    if (lastSequence_ && buffer.sequence > *lastSequence_ + 1) {
        const uint32_t gap = buffer.sequence - *lastSequence_ - 1;
        framesDropped_ += gap;
        LUMAR_LOG(Capture, Warn) << device << ": " << gap << " frame(s) dropped before sequence " << buffer.sequence
                                 << " (" << framesDropped_ << " in all)";
    }
    lastSequence_ = buffer.sequence;
    const std::string defect = bufferDefect(layout(), buffer.flags, buffer.bytesused, buffers_[buffer.index]->size());
    if (!defect.empty()) {
        countCorrupt(buffer.sequence, defect);
        queueBuffer(buffer.index);
        return false;
    }
    return true;
}

void V4l2Source::countCorrupt(uint32_t sequence, const std::string& why)
{
    ++framesCorrupt_;
    if (framesCorrupt_ == 1 || framesCorrupt_ % kCorruptLogEvery == 0) {
        LUMAR_LOG(Capture, Warn) << options_.device << ": frame " << sequence << " is corrupt (" << why
                                 << "); skipped (" << framesCorrupt_ << " corrupt in all, logged every "
                                 << kCorruptLogEvery << ")";
    }
}

void V4l2Source::returnLentBuffers()
{
    for (size_t i = 0; i < lent_.size();) {
        // The frames' handle has ended (acquire: their last reads happened before).
        if (buffers_[lent_[i]]->returned()) {
            queueBuffer(lent_[i]);
            lent_[i] = lent_.back();
            lent_.pop_back();
        } else {
            ++i;
        }
    }
}

bool V4l2Source::canLend() const
{
    // The buffer just dequeued, the lent ones, and at least two left for the driver to fill.
    constexpr size_t kKeptQueued = 2;
    return options_.zeroCopy && options_.rawYcbcr &&
           (pixelFormat_ == V4L2_PIX_FMT_NV12 || pixelFormat_ == V4L2_PIX_FMT_YUYV) &&
           buffers_.size() >= lent_.size() + 1 + kKeptQueued;
}

void V4l2Source::lendBuffer(uint32_t index, Frame& frame)
{
    YCbCrImage& raw = frame.ycbcr;
    raw.width = width_;
    raw.height = height_;
    raw.colorimetry = converter_.colorimetry();
    raw.layout = pixelFormat_ == V4L2_PIX_FMT_NV12 ? YCbCrLayout::Nv12 : YCbCrLayout::Yuyv;
    raw.plane0.clear();
    raw.plane1.clear();
    raw.stride0 = bytesPerLine_;
    raw.stride1 = pixelFormat_ == V4L2_PIX_FMT_NV12 ? bytesPerLine_ : 0;
    // The frames' own handle, with its own count: the end of its last copy gives the buffer
    // back. It holds the buffer, so the mapping outlives this source if a frame does.
    const std::shared_ptr<V4l2Buffer>& owner = buffers_[index];
    owner->lend();
    raw.buffer = std::shared_ptr<const CameraBuffer>(owner.get(), [owner](const CameraBuffer*) { owner->giveBack(); });
    lent_.push_back(index);
    converter_.convertLuma(buffers_[index]->data(), bytesPerLine_, pixelFormat_ == V4L2_PIX_FMT_NV12 ? 1 : 2, width_,
                           height_, frame.luma);
}

bool V4l2Source::next(Frame& frame)
{
    // The buffer this frame object showed last is free now (unless a copy of it lives on).
    frame.ycbcr.buffer.reset();
    returnLentBuffers();
    v4l2_buffer buffer{};
    // One deadline for the whole call, so a camera sending nothing but corrupt frames times
    // out like a silent one instead of keeping the caller here for ever.
    const int64_t deadline = monotonicNowNs() + int64_t(options_.frameTimeoutMs) * 1'000'000;
    corruptAtCallStart_ = framesCorrupt_;
    for (;;) {
        if (!dequeueGoodBuffer(buffer, deadline)) {
            continue;
        }
        const int64_t convertStart = monotonicNowNs();
        if (canLend()) {
            lendBuffer(buffer.index, frame); // queued again once no frame holds it
            lastConversionNs_ = monotonicNowNs() - convertStart;
            break;
        }
        const bool converted = convert(buffers_[buffer.index]->data(), buffer.bytesused, frame);
        lastConversionNs_ = monotonicNowNs() - convertStart;
        queueBuffer(buffer.index);
        if (converted) {
            break;
        }
        countCorrupt(buffer.sequence, decodeError_);
    }
    const bool monotonic = (buffer.flags & V4L2_BUF_FLAG_TIMESTAMP_MASK) == V4L2_BUF_FLAG_TIMESTAMP_MONOTONIC;
    frame.sequence = buffer.sequence;
    // A driver without monotonic timestamps gets the dequeue time: late, but on the right clock.
    frame.timestampNs =
        monotonic ? int64_t(buffer.timestamp.tv_sec) * 1'000'000'000 + int64_t(buffer.timestamp.tv_usec) * 1000
                  : monotonicNowNs();
    frame.capturedNs = frame.timestampNs;
    return true;
}

V4l2FrameLayout V4l2Source::layout() const
{
    return {pixelFormat_, width_, height_, bytesPerLine_, imageSize_};
}

bool V4l2Source::convert(const uint8_t* data, size_t bytesUsed, Frame& frame)
{
    return convertV4l2Frame(layout(), converter_, mjpeg_.get(), options_.rawYcbcr, data, bytesUsed, frame,
                            decodeError_);
}

} // namespace lumar
