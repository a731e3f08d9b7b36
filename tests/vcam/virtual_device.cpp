#include "vcam/virtual_device.h"

#include <algorithm>
#include <array>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <limits>

#include <poll.h>
#include <sys/mman.h>
#include <unistd.h>

#include "vcam/real_libc.h"
#include "vcam/vcam_pattern.h"

namespace lumar::vcam {
namespace {

struct Size {
    uint32_t width;
    uint32_t height;
};
constexpr std::array<Size, 2> kSizes{{{640, 480}, {1280, 720}}};
constexpr std::array<v4l2_fract, 3> kIntervals{{{1, 60}, {1, 30}, {1, 15}}};
constexpr uint32_t kMinBuffers = 2;
constexpr uint32_t kMaxBuffers = 8;

const char* formatName(uint32_t pixelFormat)
{
    switch (pixelFormat) {
    case V4L2_PIX_FMT_YUYV:
        return "YUYV 4:2:2";
    case V4L2_PIX_FMT_NV12:
        return "Y/UV 4:2:0";
    default:
        return "8-bit Greyscale";
    }
}

} // namespace

bool VirtualDevice::supportedFormat(uint32_t pixelFormat) const
{
    const auto& formats = settings_.pixelFormats;
    return std::find(formats.begin(), formats.end(), pixelFormat) != formats.end();
}

namespace {

bool supportedSize(uint32_t width, uint32_t height)
{
    return std::any_of(kSizes.begin(), kSizes.end(), [&](Size s) { return s.width == width && s.height == height; });
}

void copyName(uint8_t* out, size_t capacity, const char* text)
{
    std::strncpy(reinterpret_cast<char*>(out), text, capacity - 1);
    out[capacity - 1] = 0;
}

} // namespace

VirtualDevice::VirtualDevice(Settings settings, bool nonBlocking)
    : settings_(std::move(settings)), nonBlocking_(nonBlocking)
{
    format_.width = kSizes[0].width;
    format_.height = kSizes[0].height;
    format_.pixelformat = settings_.pixelFormats.front();
    setFormat(format_);
}

VirtualDevice::~VirtualDevice()
{
    releaseBuffers();
}

void VirtualDevice::setFormat(v4l2_pix_format& format) const
{
    if (!supportedFormat(format.pixelformat)) {
        format.pixelformat = settings_.pixelFormats.front(); // V4L2 drivers substitute, they do not refuse
    }
    // The closest offered size by area.
    const auto area = [](uint32_t w, uint32_t h) { return int64_t(w) * int64_t(h); };
    Size best = kSizes[0];
    for (Size s : kSizes) {
        if (std::llabs(area(s.width, s.height) - area(format.width, format.height)) <
            std::llabs(area(best.width, best.height) - area(format.width, format.height))) {
            best = s;
        }
    }
    format.width = best.width;
    format.height = best.height;
    format.field = V4L2_FIELD_NONE;
    format.bytesperline = format.width * (format.pixelformat == V4L2_PIX_FMT_YUYV ? 2 : 1);
    const uint32_t plane = format.bytesperline * format.height;
    format.sizeimage = format.pixelformat == V4L2_PIX_FMT_NV12 ? plane + plane / 2 : plane;
    format.colorspace = settings_.bt709 ? V4L2_COLORSPACE_REC709 : V4L2_COLORSPACE_SMPTE170M;
    format.ycbcr_enc = settings_.bt709 ? V4L2_YCBCR_ENC_709 : V4L2_YCBCR_ENC_601;
    format.quantization = settings_.fullRange ? V4L2_QUANTIZATION_FULL_RANGE : V4L2_QUANTIZATION_LIM_RANGE;
    format.xfer_func = V4L2_XFER_FUNC_709;
    format.flags = 0;
    format.priv = 0;
}

int64_t VirtualDevice::frameDueNs(int64_t frameIndex) const
{
    const int64_t periodNs = int64_t(timePerFrame_.numerator) * 1'000'000'000 / int64_t(timePerFrame_.denominator);
    int64_t due = streamStartNs_ + (frameIndex + 1) * periodNs;
    if (settings_.stallAt >= 0 && frameIndex >= settings_.stallAt) {
        due += settings_.stallMs * 1'000'000;
    }
    return due;
}

int64_t VirtualDevice::nextFrameDueNs() const
{
    if (!streaming_ || unplugged_) {
        return std::numeric_limits<int64_t>::max();
    }
    return frameDueNs(frameIndex_);
}

void VirtualDevice::advance(int64_t nowNs)
{
    while (streaming_ && !unplugged_ && frameDueNs(frameIndex_) <= nowNs) {
        const int64_t index = frameIndex_;
        if (settings_.unplugAt >= 0 && index >= settings_.unplugAt) {
            unplugged_ = true;
            return;
        }
        ++frameIndex_;
        const bool dropped = settings_.dropEvery > 0 && (index + 1) % settings_.dropEvery == 0;
        if (dropped || queued_.empty()) {
            continue; // the sequence number is spent, no buffer filled
        }
        const uint32_t bufferIndex = queued_.front();
        queued_.pop_front();
        Buffer& buffer = buffers_[bufferIndex];
        PatternFormat pattern{format_.pixelformat,  int(format_.width), int(format_.height),
                              format_.bytesperline, settings_.bt709,    settings_.fullRange};
        drawPattern(pattern, index, memory_ + size_t(bufferIndex) * bufferStride_);
        buffer.state = BufferState::Done;
        buffer.sequence = uint32_t(index);
        buffer.timestampNs = frameDueNs(index);
        const bool shortened = settings_.shortEvery > 0 && (index + 1) % settings_.shortEvery == 0;
        buffer.bytesUsed = shortened ? format_.sizeimage / 2 : format_.sizeimage;
        done_.push_back(bufferIndex);
    }
}

short VirtualDevice::pollEvents(int64_t nowNs)
{
    advance(nowNs);
    if (unplugged_) {
        return POLLERR | POLLHUP;
    }
    if (!streaming_ || (queued_.empty() && done_.empty())) {
        return POLLERR;
    }
    return done_.empty() ? short(0) : short(POLLIN | POLLRDNORM);
}

int VirtualDevice::memfdForMapping(size_t length, off_t offset, int& error) const
{
    if (unplugged_) {
        error = ENODEV;
        return -1;
    }
    if (buffers_.empty() || offset < 0 || size_t(offset) % bufferStride_ != 0 ||
        size_t(offset) / bufferStride_ >= buffers_.size() || length == 0 || length > bufferStride_) {
        error = EINVAL;
        return -1;
    }
    return memfd_;
}

void VirtualDevice::releaseBuffers()
{
    if (memory_ != nullptr) {
        real::munmap(memory_, memorySize_);
        memory_ = nullptr;
    }
    if (memfd_ >= 0) {
        real::close(memfd_);
        memfd_ = -1;
    }
    memorySize_ = 0;
    buffers_.clear();
    queued_.clear();
    done_.clear();
}

void VirtualDevice::stopStreaming()
{
    streaming_ = false;
    queued_.clear();
    done_.clear();
    for (Buffer& buffer : buffers_) {
        buffer.state = BufferState::Dequeued;
    }
}

int VirtualDevice::requestBuffers(v4l2_requestbuffers& request)
{
    if (request.type != V4L2_BUF_TYPE_VIDEO_CAPTURE || request.memory != V4L2_MEMORY_MMAP) {
        return EINVAL;
    }
    if (streaming_) {
        return EBUSY;
    }
    releaseBuffers();
    request.capabilities = V4L2_BUF_CAP_SUPPORTS_MMAP;
    if (request.count == 0) {
        return 0;
    }
    request.count = std::clamp(request.count, kMinBuffers, kMaxBuffers);
    const size_t page = size_t(sysconf(_SC_PAGESIZE));
    bufferStride_ = (size_t(format_.sizeimage) + page - 1) / page * page;
    memorySize_ = bufferStride_ * request.count;
    memfd_ = memfd_create("lumar-vcam-buffers", MFD_CLOEXEC);
    if (memfd_ < 0 || ftruncate(memfd_, off_t(memorySize_)) != 0) {
        const int error = errno;
        releaseBuffers();
        return error;
    }
    void* memory = real::mmap(nullptr, memorySize_, PROT_READ | PROT_WRITE, MAP_SHARED, memfd_, 0);
    if (memory == MAP_FAILED) {
        const int error = errno;
        releaseBuffers();
        return error;
    }
    memory_ = static_cast<uint8_t*>(memory);
    buffers_.assign(request.count, Buffer{});
    return 0;
}

void VirtualDevice::describeBuffer(uint32_t index, v4l2_buffer& out) const
{
    const Buffer& buffer = buffers_[index];
    const uint32_t type = out.type;
    std::memset(&out, 0, sizeof out);
    out.index = index;
    out.type = type;
    out.memory = V4L2_MEMORY_MMAP;
    out.m.offset = uint32_t(size_t(index) * bufferStride_);
    out.length = format_.sizeimage;
    out.field = V4L2_FIELD_NONE;
    out.flags = V4L2_BUF_FLAG_MAPPED | V4L2_BUF_FLAG_TIMESTAMP_MONOTONIC | V4L2_BUF_FLAG_TSTAMP_SRC_EOF;
    if (buffer.state == BufferState::Queued) {
        out.flags |= V4L2_BUF_FLAG_QUEUED;
    }
    if (buffer.state == BufferState::Done) {
        out.flags |= V4L2_BUF_FLAG_DONE;
        out.bytesused = buffer.bytesUsed;
        out.sequence = buffer.sequence;
        out.timestamp.tv_sec = buffer.timestampNs / 1'000'000'000;
        out.timestamp.tv_usec = (buffer.timestampNs % 1'000'000'000) / 1000;
    }
}

int VirtualDevice::queryCapability(v4l2_capability& capability) const
{
    std::memset(&capability, 0, sizeof capability);
    copyName(capability.driver, sizeof capability.driver, "lumar_vcam");
    copyName(capability.card, sizeof capability.card, "Lumar virtual camera");
    copyName(capability.bus_info, sizeof capability.bus_info, "platform:lumar-vcam");
    capability.version = (6u << 16) | (1u << 8);
    capability.device_caps = V4L2_CAP_VIDEO_CAPTURE | V4L2_CAP_STREAMING;
    capability.capabilities = capability.device_caps | V4L2_CAP_DEVICE_CAPS;
    return 0;
}

int VirtualDevice::enumerateFormat(v4l2_fmtdesc& description) const
{
    if (description.type != V4L2_BUF_TYPE_VIDEO_CAPTURE || description.index >= settings_.pixelFormats.size()) {
        return EINVAL;
    }
    const uint32_t index = description.index;
    const uint32_t type = description.type;
    std::memset(&description, 0, sizeof description);
    description.index = index;
    description.type = type;
    description.pixelformat = settings_.pixelFormats[index];
    copyName(description.description, sizeof description.description, formatName(description.pixelformat));
    return 0;
}

int VirtualDevice::enumerateFrameSize(v4l2_frmsizeenum& size) const
{
    if (!supportedFormat(size.pixel_format) || size.index >= kSizes.size()) {
        return EINVAL;
    }
    size.type = V4L2_FRMSIZE_TYPE_DISCRETE;
    size.discrete.width = kSizes[size.index].width;
    size.discrete.height = kSizes[size.index].height;
    return 0;
}

int VirtualDevice::enumerateFrameInterval(v4l2_frmivalenum& interval) const
{
    if (!supportedFormat(interval.pixel_format) || !supportedSize(interval.width, interval.height) ||
        interval.index >= kIntervals.size()) {
        return EINVAL;
    }
    interval.type = V4L2_FRMIVAL_TYPE_DISCRETE;
    interval.discrete = kIntervals[interval.index];
    return 0;
}

int VirtualDevice::setOrTryFormat(v4l2_format& format, bool apply)
{
    if (format.type != V4L2_BUF_TYPE_VIDEO_CAPTURE) {
        return EINVAL;
    }
    setFormat(format.fmt.pix);
    if (apply) {
        if (streaming_ || !buffers_.empty()) {
            return EBUSY;
        }
        format_ = format.fmt.pix;
    }
    return 0;
}

int VirtualDevice::frameRateParameters(v4l2_streamparm& parameters, bool apply)
{
    if (parameters.type != V4L2_BUF_TYPE_VIDEO_CAPTURE) {
        return EINVAL;
    }
    if (apply) {
        const v4l2_fract requested = parameters.parm.capture.timeperframe;
        if (streaming_) {
            return EBUSY;
        }
        if (requested.numerator > 0 && requested.denominator > 0) {
            // The offered interval closest to the request.
            const double wanted = double(requested.numerator) / requested.denominator;
            timePerFrame_ = *std::min_element(kIntervals.begin(), kIntervals.end(), [&](v4l2_fract a, v4l2_fract b) {
                return std::abs(double(a.numerator) / a.denominator - wanted) <
                       std::abs(double(b.numerator) / b.denominator - wanted);
            });
        }
    }
    std::memset(&parameters.parm, 0, sizeof parameters.parm);
    parameters.parm.capture.capability = V4L2_CAP_TIMEPERFRAME;
    parameters.parm.capture.timeperframe = timePerFrame_;
    parameters.parm.capture.readbuffers = 0;
    return 0;
}

int VirtualDevice::queueBuffer(v4l2_buffer& buffer)
{
    if (buffer.type != V4L2_BUF_TYPE_VIDEO_CAPTURE || buffer.memory != V4L2_MEMORY_MMAP ||
        buffer.index >= buffers_.size() || buffers_[buffer.index].state != BufferState::Dequeued) {
        return EINVAL;
    }
    buffers_[buffer.index].state = BufferState::Queued;
    queued_.push_back(buffer.index);
    describeBuffer(buffer.index, buffer);
    return 0;
}

int VirtualDevice::dequeueBuffer(v4l2_buffer& buffer)
{
    if (buffer.type != V4L2_BUF_TYPE_VIDEO_CAPTURE || buffer.memory != V4L2_MEMORY_MMAP) {
        return EINVAL;
    }
    if (!streaming_) {
        return EINVAL;
    }
    if (done_.empty()) {
        return EAGAIN;
    }
    const uint32_t index = done_.front();
    done_.pop_front();
    describeBuffer(index, buffer);
    buffers_[index].state = BufferState::Dequeued;
    return 0;
}

int VirtualDevice::ioctl(unsigned long request, void* arg, int64_t nowNs)
{
    advance(nowNs);
    if (unplugged_) {
        return ENODEV;
    }
    if (arg == nullptr) {
        return EFAULT;
    }
    switch (request) {
    case VIDIOC_QUERYCAP:
        return queryCapability(*static_cast<v4l2_capability*>(arg));
    case VIDIOC_ENUM_FMT:
        return enumerateFormat(*static_cast<v4l2_fmtdesc*>(arg));
    case VIDIOC_ENUM_FRAMESIZES:
        return enumerateFrameSize(*static_cast<v4l2_frmsizeenum*>(arg));
    case VIDIOC_ENUM_FRAMEINTERVALS:
        return enumerateFrameInterval(*static_cast<v4l2_frmivalenum*>(arg));
    case VIDIOC_G_FMT: {
        auto& format = *static_cast<v4l2_format*>(arg);
        if (format.type != V4L2_BUF_TYPE_VIDEO_CAPTURE) {
            return EINVAL;
        }
        format.fmt.pix = format_;
        return 0;
    }
    case VIDIOC_S_FMT:
        return setOrTryFormat(*static_cast<v4l2_format*>(arg), true);
    case VIDIOC_TRY_FMT:
        return setOrTryFormat(*static_cast<v4l2_format*>(arg), false);
    case VIDIOC_G_PARM:
        return frameRateParameters(*static_cast<v4l2_streamparm*>(arg), false);
    case VIDIOC_S_PARM:
        return frameRateParameters(*static_cast<v4l2_streamparm*>(arg), true);
    case VIDIOC_REQBUFS:
        return requestBuffers(*static_cast<v4l2_requestbuffers*>(arg));
    case VIDIOC_QUERYBUF: {
        auto& buffer = *static_cast<v4l2_buffer*>(arg);
        if (buffer.type != V4L2_BUF_TYPE_VIDEO_CAPTURE || buffer.index >= buffers_.size()) {
            return EINVAL;
        }
        describeBuffer(buffer.index, buffer);
        return 0;
    }
    case VIDIOC_QBUF:
        return queueBuffer(*static_cast<v4l2_buffer*>(arg));
    case VIDIOC_DQBUF:
        return dequeueBuffer(*static_cast<v4l2_buffer*>(arg));
    case VIDIOC_STREAMON:
    case VIDIOC_STREAMOFF: {
        if (*static_cast<int*>(arg) != V4L2_BUF_TYPE_VIDEO_CAPTURE) {
            return EINVAL;
        }
        if (request == VIDIOC_STREAMOFF) {
            stopStreaming();
            return 0;
        }
        if (buffers_.empty()) {
            return EINVAL;
        }
        if (!streaming_) {
            streaming_ = true;
            streamStartNs_ = nowNs;
            frameIndex_ = 0;
        }
        return 0;
    }
    case VIDIOC_ENUMINPUT: {
        auto& input = *static_cast<v4l2_input*>(arg);
        if (input.index != 0) {
            return EINVAL;
        }
        std::memset(&input, 0, sizeof input);
        copyName(input.name, sizeof input.name, "Camera");
        input.type = V4L2_INPUT_TYPE_CAMERA;
        return 0;
    }
    case VIDIOC_G_INPUT:
        *static_cast<int*>(arg) = 0;
        return 0;
    case VIDIOC_S_INPUT:
        return *static_cast<int*>(arg) == 0 ? 0 : EINVAL;
    default:
        return ENOTTY; // what V4L2 answers for an ioctl a driver does not implement
    }
}

} // namespace lumar::vcam
