#include "vcam/virtual_device.h"

#include <algorithm>
#include <array>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <limits>

#include <fcntl.h>
#include <poll.h>
#include <sys/mman.h>
#include <time.h>
#include <unistd.h>

#include "vcam/real_libc.h"
#include "vcam/vcam_pattern.h"

namespace lumar::vcam {
namespace {

// 120 fps first: v4l2-compliance streams at the first interval offered, so its run stays short.
constexpr std::array<v4l2_fract, 4> kIntervals{{{1, 120}, {1, 60}, {1, 30}, {1, 15}}};
constexpr uint32_t kMinBuffers = 2;
constexpr uint32_t kMaxBuffers = 32;
// Freed buffers that are still mapped stay valid (they are memfd mappings), as vb2's
// "orphaned buffers" are.
constexpr uint32_t kBufferCapabilities = V4L2_BUF_CAP_SUPPORTS_MMAP | V4L2_BUF_CAP_SUPPORTS_ORPHANED_BUFS;

// The kernel's descriptions (v4l2-ioctl.c), which v4l2-compliance compares against.
const char* formatName(uint32_t pixelFormat)
{
    switch (pixelFormat) {
    case V4L2_PIX_FMT_YUYV:
        return "YUYV 4:2:2";
    case V4L2_PIX_FMT_NV12:
        return "Y/CbCr 4:2:0";
    case V4L2_PIX_FMT_MJPEG:
        return "Motion-JPEG";
    default:
        return "8-bit Greyscale";
    }
}

void copyName(uint8_t* out, size_t capacity, const char* text)
{
    std::memset(out, 0, capacity);
    std::strncpy(reinterpret_cast<char*>(out), text, capacity - 1);
}

bool isCaptureType(uint32_t type)
{
    return type == V4L2_BUF_TYPE_VIDEO_CAPTURE;
}

} // namespace

VirtualDevice::VirtualDevice(Settings settings) : settings_(std::move(settings)), sizes_{{640, 480}, {1280, 720}}
{
    format_.width = sizes_[0].width;
    format_.height = sizes_[0].height;
    format_.pixelformat = settings_.pixelFormats.front();
    setFormat(format_);
}

VirtualDevice::~VirtualDevice()
{
    releaseBuffers();
}

int VirtualDevice::openHandle()
{
    const int id = nextHandle_++;
    handles_[id] = Handle{};
    return id;
}

void VirtualDevice::closeHandle(int handle)
{
    if (owner_ == handle) {
        stopStreaming();
        releaseBuffers();
    }
    handles_.erase(handle);
}

bool VirtualDevice::supportedFormat(uint32_t pixelFormat) const
{
    const auto& formats = settings_.pixelFormats;
    return std::find(formats.begin(), formats.end(), pixelFormat) != formats.end();
}

bool VirtualDevice::supportedSize(uint32_t width, uint32_t height) const
{
    return std::any_of(sizes_.begin(), sizes_.end(), [&](Size s) { return s.width == width && s.height == height; });
}

void VirtualDevice::setFormat(v4l2_pix_format& format) const
{
    if (!supportedFormat(format.pixelformat)) {
        format.pixelformat = settings_.pixelFormats.front(); // V4L2 drivers substitute, they do not refuse
    }
    // The closest offered size by area.
    const auto area = [](uint32_t w, uint32_t h) { return int64_t(w) * int64_t(h); };
    Size best = sizes_[0];
    for (Size s : sizes_) {
        if (std::llabs(area(s.width, s.height) - area(format.width, format.height)) <
            std::llabs(area(best.width, best.height) - area(format.width, format.height))) {
            best = s;
        }
    }
    const uint32_t pixelFormat = format.pixelformat;
    std::memset(&format, 0, sizeof format);
    format.pixelformat = pixelFormat;
    format.width = best.width;
    format.height = best.height;
    format.field = V4L2_FIELD_NONE;
    if (pixelFormat == V4L2_PIX_FMT_MJPEG) {
        // Compressed: no lines; room for the worst case of a 4:2:2 JPEG.
        format.bytesperline = 0;
        format.sizeimage = format.width * format.height * 2;
        format.colorspace = V4L2_COLORSPACE_JPEG;
        format.ycbcr_enc = V4L2_YCBCR_ENC_601;
        format.quantization = V4L2_QUANTIZATION_FULL_RANGE;
        format.xfer_func = V4L2_XFER_FUNC_SRGB;
    } else {
        format.bytesperline = format.width * (pixelFormat == V4L2_PIX_FMT_YUYV ? 2 : 1);
        const uint32_t plane = format.bytesperline * format.height;
        format.sizeimage = pixelFormat == V4L2_PIX_FMT_NV12 ? plane + plane / 2 : plane;
        format.colorspace = settings_.bt709 ? V4L2_COLORSPACE_REC709 : V4L2_COLORSPACE_SMPTE170M;
        format.ycbcr_enc = settings_.bt709 ? V4L2_YCBCR_ENC_709 : V4L2_YCBCR_ENC_601;
        format.quantization = settings_.fullRange ? V4L2_QUANTIZATION_FULL_RANGE : V4L2_QUANTIZATION_LIM_RANGE;
        format.xfer_func = V4L2_XFER_FUNC_709;
    }
    format.priv = V4L2_PIX_FMT_PRIV_MAGIC; // the extended fields are valid (V4L2_CAP_EXT_PIX_FORMAT)
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
    if (!streaming_ || unplugged_ || sourceChanged_) {
        return std::numeric_limits<int64_t>::max();
    }
    return settings_.paced ? pacedDueNs() : frameDueNs(frameIndex_);
}

void VirtualDevice::fillBuffer(Buffer& buffer, int64_t index)
{
    const bool shortened = settings_.shortEvery > 0 && (index + 1) % settings_.shortEvery == 0;
    if (format_.pixelformat == V4L2_PIX_FMT_MJPEG) {
        const std::vector<uint8_t>& jpeg =
            mjpeg_.frame(index, int(format_.width), int(format_.height), int(settings_.jpegQuality));
        const bool corrupt = settings_.corruptEvery > 0 && (index + 1) % settings_.corruptEvery == 0;
        if (corrupt) {
            buffer.bytesUsed = uint32_t(corruptJpeg(jpeg, buffer.memory, buffer.length));
        } else {
            const size_t size = std::min(jpeg.size(), buffer.length);
            std::memcpy(buffer.memory, jpeg.data(), size);
            buffer.bytesUsed = uint32_t(size);
        }
        if (shortened) {
            buffer.bytesUsed /= 2;
        }
        return;
    }
    PatternFormat pattern{format_.pixelformat,  int(format_.width), int(format_.height),
                          format_.bytesperline, settings_.bt709,    settings_.fullRange};
    drawPattern(pattern, index, buffer.memory);
    buffer.bytesUsed = shortened ? format_.sizeimage / 2 : format_.sizeimage;
}

int64_t VirtualDevice::pacedDueNs() const
{
    if (!done_.empty() || queued_.empty()) {
        return std::numeric_limits<int64_t>::max();
    }
    return std::max(frameDueNs(frameIndex_), pacedNotBeforeNs_);
}

void VirtualDevice::advance(int64_t nowNs)
{
    while (streaming_ && !unplugged_ && !sourceChanged_ &&
           (settings_.paced ? pacedDueNs() : frameDueNs(frameIndex_)) <= nowNs) {
        const int64_t index = frameIndex_;
        if (settings_.unplugAt >= 0 && index >= settings_.unplugAt) {
            unplugged_ = true;
            return;
        }
        if (settings_.sourceChangeAt >= 0 && framesProduced_ == settings_.sourceChangeAt) {
            // The input now delivers another size: stop, announce, offer only the new size.
            ++framesProduced_;
            sourceChanged_ = true;
            sizes_ = {{settings_.sourceChangeWidth, settings_.sourceChangeHeight}};
            format_.width = settings_.sourceChangeWidth;
            format_.height = settings_.sourceChangeHeight;
            setFormat(format_);
            for (auto& [id, handle] : handles_) {
                const bool subscribed =
                    std::any_of(handle.subscriptions.begin(), handle.subscriptions.end(),
                                [](const v4l2_event_subscription& s) { return s.type == V4L2_EVENT_SOURCE_CHANGE; });
                if (subscribed) {
                    v4l2_event event{};
                    event.type = V4L2_EVENT_SOURCE_CHANGE;
                    event.u.src_change.changes = V4L2_EVENT_SRC_CH_RESOLUTION;
                    raiseEvent(handle, event);
                }
            }
            return;
        }
        const bool dropped = settings_.dropEvery > 0 && (index + 1) % settings_.dropEvery == 0;
        ++frameIndex_;
        ++framesProduced_;
        if (dropped || queued_.empty()) {
            continue; // the sequence number is spent, no buffer filled
        }
        const uint32_t bufferIndex = queued_.front();
        queued_.pop_front();
        Buffer& buffer = buffers_[bufferIndex];
        fillBuffer(buffer, index);
        buffer.state = BufferState::Done;
        buffer.sequence = uint32_t(index);
        buffer.timestampNs = frameDueNs(index);
        done_.push_back(bufferIndex);
        const int64_t periodNs = int64_t(timePerFrame_.numerator) * 1'000'000'000 / int64_t(timePerFrame_.denominator);
        pacedNotBeforeNs_ = nowNs + periodNs;
    }
}

short VirtualDevice::pollEvents(int handle, short requested, int64_t nowNs)
{
    advance(nowNs);
    if (unplugged_) {
        return POLLERR | POLLHUP;
    }
    short events = 0;
    if (const auto found = handles_.find(handle); found != handles_.end() && !found->second.events.empty()) {
        events |= POLLPRI;
    }
    // As vb2: without POLLIN asked, the buffer queue adds nothing (not even POLLERR).
    if (!(requested & (POLLIN | POLLRDNORM))) {
        return events;
    }
    if (!streaming_ || (queued_.empty() && done_.empty())) {
        return short(events | POLLERR);
    }
    return done_.empty() ? events : short(events | POLLIN | POLLRDNORM);
}

int VirtualDevice::memfdForMapping(size_t length, off_t offset, int& error) const
{
    if (unplugged_) {
        error = ENODEV;
        return -1;
    }
    for (const Buffer& buffer : buffers_) {
        if (offset >= 0 && size_t(offset) == buffer.offset && length > 0 && length <= buffer.length) {
            return buffer.memfd;
        }
    }
    error = EINVAL;
    return -1;
}

void VirtualDevice::releaseBuffers()
{
    for (Buffer& buffer : buffers_) {
        if (buffer.memory != nullptr) {
            real::munmap(buffer.memory, buffer.length);
        }
        if (buffer.memfd >= 0) {
            real::close(buffer.memfd);
        }
    }
    buffers_.clear();
    queued_.clear();
    done_.clear();
    owner_ = -1;
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

bool VirtualDevice::busyFor(int handle) const
{
    return owner_ != -1 && owner_ != handle;
}

v4l2_priority VirtualDevice::maxPriority() const
{
    v4l2_priority highest = V4L2_PRIORITY_BACKGROUND;
    for (const auto& [id, handle] : handles_) {
        highest = std::max(highest, handle.priority);
    }
    return highest;
}

int VirtualDevice::priorityCheck(int handle) const
{
    const auto found = handles_.find(handle);
    return found != handles_.end() && found->second.priority < maxPriority() ? EBUSY : 0;
}

int VirtualDevice::allocate(uint32_t count, size_t size)
{
    const size_t page = size_t(sysconf(_SC_PAGESIZE));
    const size_t length = (size + page - 1) / page * page;
    for (uint32_t i = 0; i < count; ++i) {
        Buffer buffer;
        buffer.length = length;
        buffer.offset = buffers_.empty() ? 0 : buffers_.back().offset + buffers_.back().length;
        // One memfd per buffer: what VIDIOC_EXPBUF hands out, as a dmabuf fd of one buffer.
        buffer.memfd = memfd_create("lumar-vcam-buffer", MFD_CLOEXEC);
        if (buffer.memfd < 0 || ftruncate(buffer.memfd, off_t(length)) != 0) {
            const int error = errno;
            if (buffer.memfd >= 0) {
                real::close(buffer.memfd);
            }
            return error;
        }
        void* memory = real::mmap(nullptr, length, PROT_READ | PROT_WRITE, MAP_SHARED, buffer.memfd, 0);
        if (memory == MAP_FAILED) {
            const int error = errno;
            real::close(buffer.memfd);
            return error;
        }
        buffer.memory = static_cast<uint8_t*>(memory);
        buffers_.push_back(buffer);
    }
    return 0;
}

int VirtualDevice::requestBuffers(int handle, v4l2_requestbuffers& request)
{
    if (!isCaptureType(request.type) || request.memory != V4L2_MEMORY_MMAP) {
        return EINVAL;
    }
    if (busyFor(handle)) {
        return EBUSY;
    }
    if (streaming_) {
        return EBUSY;
    }
    releaseBuffers();
    request.capabilities = kBufferCapabilities;
    request.flags = 0; // no cache hints
    std::memset(request.reserved, 0, sizeof request.reserved);
    if (request.count == 0) {
        return 0;
    }
    request.count = std::clamp(request.count, kMinBuffers, kMaxBuffers);
    if (const int error = allocate(request.count, format_.sizeimage); error != 0) {
        releaseBuffers();
        return error;
    }
    owner_ = handle;
    return 0;
}

int VirtualDevice::createBuffers(int handle, v4l2_create_buffers& request)
{
    if (!isCaptureType(request.format.type) || request.memory != V4L2_MEMORY_MMAP) {
        return EINVAL;
    }
    if (busyFor(handle)) {
        return EBUSY;
    }
    request.capabilities = kBufferCapabilities;
    request.flags = 0;
    std::memset(request.reserved, 0, sizeof request.reserved);
    request.index = uint32_t(buffers_.size());
    if (request.count == 0) {
        return 0;
    }
    // The format says how big each buffer must be; it may not be smaller than the current one.
    const uint32_t size = request.format.fmt.pix.sizeimage;
    if (size < format_.sizeimage) {
        return EINVAL;
    }
    const uint32_t room = kMaxBuffers - uint32_t(buffers_.size());
    request.count = std::min(request.count, room);
    if (request.count == 0) {
        return ENOBUFS;
    }
    if (const int error = allocate(request.count, size); error != 0) {
        return error;
    }
    owner_ = handle;
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
    out.m.offset = uint32_t(buffer.offset);
    out.length = uint32_t(buffer.length);
    out.field = V4L2_FIELD_NONE;
    out.flags = V4L2_BUF_FLAG_MAPPED | V4L2_BUF_FLAG_TIMESTAMP_MONOTONIC | V4L2_BUF_FLAG_TSTAMP_SRC_EOF;
    if (buffer.state == BufferState::Queued) {
        out.flags |= V4L2_BUF_FLAG_QUEUED;
    }
    if (buffer.state == BufferState::Done) {
        out.flags |= V4L2_BUF_FLAG_DONE;
    }
}

int VirtualDevice::queryCapability(v4l2_capability& capability) const
{
    std::memset(&capability, 0, sizeof capability);
    copyName(capability.driver, sizeof capability.driver, "lumar_vcam");
    copyName(capability.card, sizeof capability.card, "Lumar virtual camera");
    copyName(capability.bus_info, sizeof capability.bus_info, "platform:lumar-vcam");
    capability.version = (6u << 16) | (1u << 8);
    capability.device_caps = V4L2_CAP_VIDEO_CAPTURE | V4L2_CAP_STREAMING | V4L2_CAP_EXT_PIX_FORMAT;
    capability.capabilities = capability.device_caps | V4L2_CAP_DEVICE_CAPS;
    return 0;
}

int VirtualDevice::enumerateFormat(v4l2_fmtdesc& description) const
{
    if (!isCaptureType(description.type) || description.index >= settings_.pixelFormats.size()) {
        return EINVAL;
    }
    const uint32_t index = description.index;
    const uint32_t type = description.type;
    std::memset(&description, 0, sizeof description);
    description.index = index;
    description.type = type;
    description.pixelformat = settings_.pixelFormats[index];
    if (description.pixelformat == V4L2_PIX_FMT_MJPEG) {
        description.flags = V4L2_FMT_FLAG_COMPRESSED;
    }
    copyName(description.description, sizeof description.description, formatName(description.pixelformat));
    return 0;
}

int VirtualDevice::enumerateFrameSize(v4l2_frmsizeenum& size) const
{
    if (!supportedFormat(size.pixel_format) || size.index >= sizes_.size()) {
        return EINVAL;
    }
    std::memset(size.reserved, 0, sizeof size.reserved);
    size.type = V4L2_FRMSIZE_TYPE_DISCRETE;
    size.discrete.width = sizes_[size.index].width;
    size.discrete.height = sizes_[size.index].height;
    return 0;
}

int VirtualDevice::enumerateFrameInterval(v4l2_frmivalenum& interval) const
{
    if (!supportedFormat(interval.pixel_format) || !supportedSize(interval.width, interval.height) ||
        interval.index >= kIntervals.size()) {
        return EINVAL;
    }
    std::memset(interval.reserved, 0, sizeof interval.reserved);
    interval.type = V4L2_FRMIVAL_TYPE_DISCRETE;
    interval.discrete = kIntervals[interval.index];
    return 0;
}

int VirtualDevice::setOrTryFormat(int handle, v4l2_format& format, bool apply)
{
    if (!isCaptureType(format.type)) {
        return EINVAL;
    }
    if (apply) {
        if (const int error = priorityCheck(handle); error != 0) {
            return error;
        }
        if (streaming_ || !buffers_.empty()) {
            return EBUSY;
        }
    }
    setFormat(format.fmt.pix);
    if (apply) {
        format_ = format.fmt.pix;
    }
    return 0;
}

int VirtualDevice::frameRateParameters(v4l2_streamparm& parameters, bool apply)
{
    if (!isCaptureType(parameters.type)) {
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

int VirtualDevice::queueBuffer(int handle, v4l2_buffer& buffer)
{
    if (!isCaptureType(buffer.type) || buffer.memory != V4L2_MEMORY_MMAP || buffer.index >= buffers_.size()) {
        return EINVAL;
    }
    if (busyFor(handle)) {
        return EBUSY;
    }
    if (buffers_[buffer.index].state != BufferState::Dequeued) {
        return EINVAL;
    }
    buffers_[buffer.index].state = BufferState::Queued;
    queued_.push_back(buffer.index);
    describeBuffer(buffer.index, buffer);
    return 0;
}

int VirtualDevice::dequeueBuffer(int handle, v4l2_buffer& buffer)
{
    if (!isCaptureType(buffer.type) || buffer.memory != V4L2_MEMORY_MMAP) {
        return EINVAL;
    }
    if (busyFor(handle)) {
        return EBUSY;
    }
    if (!streaming_) {
        return EINVAL;
    }
    if (done_.empty()) {
        return EAGAIN;
    }
    const uint32_t index = done_.front();
    done_.pop_front();
    Buffer& done = buffers_[index];
    done.state = BufferState::Dequeued;
    describeBuffer(index, buffer);
    buffer.bytesused = done.bytesUsed;
    buffer.sequence = done.sequence;
    buffer.timestamp.tv_sec = done.timestampNs / 1'000'000'000;
    buffer.timestamp.tv_usec = (done.timestampNs % 1'000'000'000) / 1000;
    return 0;
}

int VirtualDevice::exportBuffer(int handle, v4l2_exportbuffer& request)
{
    if (!isCaptureType(request.type) || request.index >= buffers_.size() || request.plane != 0 ||
        (request.flags & ~(O_CLOEXEC | O_ACCMODE)) != 0) {
        return EINVAL;
    }
    if (busyFor(handle)) {
        return EBUSY;
    }
    const int fd = fcntl(buffers_[request.index].memfd, (request.flags & O_CLOEXEC) ? F_DUPFD_CLOEXEC : F_DUPFD, 0);
    if (fd < 0) {
        return errno;
    }
    request.fd = fd;
    std::memset(request.reserved, 0, sizeof request.reserved);
    return 0;
}

void VirtualDevice::raiseEvent(Handle& handle, v4l2_event event)
{
    // Kernel queues hold a few events per subscription; an unread flood keeps the newest.
    constexpr size_t kMaxPending = 64;
    timespec now{};
    clock_gettime(CLOCK_MONOTONIC, &now);
    event.timestamp = now;
    event.sequence = handle.eventSequence++;
    std::memset(event.reserved, 0, sizeof event.reserved);
    if (handle.events.size() == kMaxPending) {
        handle.events.pop_front();
    }
    handle.events.push_back(event);
}

void VirtualDevice::raiseControlEvent(int changer, const v4l2_event_ctrl& state, uint32_t id, uint32_t changes)
{
    for (auto& [handleId, handle] : handles_) {
        for (const v4l2_event_subscription& subscription : handle.subscriptions) {
            if (subscription.type != V4L2_EVENT_CTRL || subscription.id != id) {
                continue;
            }
            if (handleId == changer && !(subscription.flags & V4L2_EVENT_SUB_FL_ALLOW_FEEDBACK)) {
                continue;
            }
            v4l2_event event{};
            event.type = V4L2_EVENT_CTRL;
            event.id = id;
            event.u.ctrl = state;
            event.u.ctrl.changes = changes;
            raiseEvent(handle, event);
        }
    }
}

ControlSet::ChangeListener VirtualDevice::listenerFor(int handle)
{
    return [this, handle](const v4l2_event_ctrl& state, uint32_t id, uint32_t changes) {
        raiseControlEvent(handle, state, id, changes);
    };
}

int VirtualDevice::subscribe(Handle& handle, const v4l2_event_subscription& subscription)
{
    v4l2_event_ctrl state{};
    switch (subscription.type) {
    case V4L2_EVENT_CTRL:
        if (!controls_.describe(subscription.id, state)) {
            return EINVAL;
        }
        break;
    case V4L2_EVENT_SOURCE_CHANGE:
        if (subscription.id != 0) {
            return EINVAL; // input 0 is the only input
        }
        break;
    default:
        return EINVAL;
    }
    const auto same = [&](const v4l2_event_subscription& s) {
        return s.type == subscription.type && s.id == subscription.id;
    };
    if (std::none_of(handle.subscriptions.begin(), handle.subscriptions.end(), same)) {
        handle.subscriptions.push_back(subscription);
    }
    // The initial state of a control (not of a class control, which has none).
    if (subscription.type == V4L2_EVENT_CTRL && (subscription.flags & V4L2_EVENT_SUB_FL_SEND_INITIAL) &&
        !controls_.isClass(subscription.id)) {
        v4l2_event event{};
        event.type = V4L2_EVENT_CTRL;
        event.id = subscription.id;
        event.u.ctrl = state;
        event.u.ctrl.changes = V4L2_EVENT_CTRL_CH_VALUE | V4L2_EVENT_CTRL_CH_FLAGS;
        raiseEvent(handle, event);
    }
    return 0;
}

int VirtualDevice::unsubscribe(Handle& handle, const v4l2_event_subscription& subscription)
{
    const bool all = subscription.type == V4L2_EVENT_ALL;
    const auto matches = [&](uint32_t type, uint32_t id) {
        return all || (type == subscription.type && id == subscription.id);
    };
    std::erase_if(handle.subscriptions, [&](const v4l2_event_subscription& s) { return matches(s.type, s.id); });
    std::erase_if(handle.events, [&](const v4l2_event& e) { return matches(e.type, e.id); });
    return 0;
}

int VirtualDevice::dequeueEvent(Handle& handle, v4l2_event& event)
{
    if (handle.events.empty()) {
        return ENOENT;
    }
    event = handle.events.front();
    handle.events.pop_front();
    event.pending = uint32_t(handle.events.size());
    return 0;
}

int VirtualDevice::ioctl(int handle, unsigned long request, void* arg, int64_t nowNs)
{
    advance(nowNs);
    if (unplugged_) {
        return ENODEV;
    }
    const auto found = handles_.find(handle);
    if (found == handles_.end()) {
        return EBADF;
    }
    Handle& self = found->second;
    // Unknown requests first: V4L2 answers ENOTTY whatever the argument.
    switch (request) {
    case VIDIOC_QUERYCAP:
    case VIDIOC_ENUM_FMT:
    case VIDIOC_ENUM_FRAMESIZES:
    case VIDIOC_ENUM_FRAMEINTERVALS:
    case VIDIOC_G_FMT:
    case VIDIOC_S_FMT:
    case VIDIOC_TRY_FMT:
    case VIDIOC_G_PARM:
    case VIDIOC_S_PARM:
    case VIDIOC_REQBUFS:
    case VIDIOC_CREATE_BUFS:
    case VIDIOC_QUERYBUF:
    case VIDIOC_QBUF:
    case VIDIOC_DQBUF:
    case VIDIOC_EXPBUF:
    case VIDIOC_STREAMON:
    case VIDIOC_STREAMOFF:
    case VIDIOC_ENUMINPUT:
    case VIDIOC_G_INPUT:
    case VIDIOC_S_INPUT:
    case VIDIOC_G_PRIORITY:
    case VIDIOC_S_PRIORITY:
    case VIDIOC_QUERYCTRL:
    case VIDIOC_QUERY_EXT_CTRL:
    case VIDIOC_QUERYMENU:
    case VIDIOC_G_CTRL:
    case VIDIOC_S_CTRL:
    case VIDIOC_G_EXT_CTRLS:
    case VIDIOC_S_EXT_CTRLS:
    case VIDIOC_TRY_EXT_CTRLS:
    case VIDIOC_SUBSCRIBE_EVENT:
    case VIDIOC_UNSUBSCRIBE_EVENT:
    case VIDIOC_DQEVENT:
        break;
    case VIDIOC_LOG_STATUS:
        return 0; // nothing to log: the state is all in the answers above
    default:
        return ENOTTY; // what V4L2 answers for an ioctl a driver does not implement
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
        if (!isCaptureType(format.type)) {
            return EINVAL;
        }
        format.fmt.pix = format_;
        return 0;
    }
    case VIDIOC_S_FMT:
        return setOrTryFormat(handle, *static_cast<v4l2_format*>(arg), true);
    case VIDIOC_TRY_FMT:
        return setOrTryFormat(handle, *static_cast<v4l2_format*>(arg), false);
    case VIDIOC_G_PARM:
        return frameRateParameters(*static_cast<v4l2_streamparm*>(arg), false);
    case VIDIOC_S_PARM:
        if (const int error = priorityCheck(handle); error != 0) {
            return error;
        }
        return frameRateParameters(*static_cast<v4l2_streamparm*>(arg), true);
    case VIDIOC_REQBUFS:
        if (const int error = priorityCheck(handle); error != 0) {
            return error;
        }
        return requestBuffers(handle, *static_cast<v4l2_requestbuffers*>(arg));
    case VIDIOC_CREATE_BUFS:
        if (const int error = priorityCheck(handle); error != 0) {
            return error;
        }
        return createBuffers(handle, *static_cast<v4l2_create_buffers*>(arg));
    case VIDIOC_QUERYBUF: {
        auto& buffer = *static_cast<v4l2_buffer*>(arg);
        if (!isCaptureType(buffer.type) || buffer.index >= buffers_.size()) {
            return EINVAL;
        }
        describeBuffer(buffer.index, buffer);
        return 0;
    }
    case VIDIOC_QBUF:
        return queueBuffer(handle, *static_cast<v4l2_buffer*>(arg));
    case VIDIOC_DQBUF:
        return dequeueBuffer(handle, *static_cast<v4l2_buffer*>(arg));
    case VIDIOC_EXPBUF:
        return exportBuffer(handle, *static_cast<v4l2_exportbuffer*>(arg));
    case VIDIOC_STREAMON:
    case VIDIOC_STREAMOFF: {
        if (!isCaptureType(uint32_t(*static_cast<int*>(arg)))) {
            return EINVAL;
        }
        if (const int error = priorityCheck(handle); error != 0) {
            return error;
        }
        if (busyFor(handle)) {
            return EBUSY;
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
            sourceChanged_ = false;
            streamStartNs_ = nowNs;
            pacedNotBeforeNs_ = 0;
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
        if (const int error = priorityCheck(handle); error != 0) {
            return error;
        }
        return *static_cast<int*>(arg) == 0 ? 0 : EINVAL;
    case VIDIOC_G_PRIORITY:
        *static_cast<uint32_t*>(arg) = maxPriority();
        return 0;
    case VIDIOC_S_PRIORITY: {
        const uint32_t wanted = *static_cast<uint32_t*>(arg);
        if (wanted > V4L2_PRIORITY_RECORD) {
            return EINVAL;
        }
        if (const int error = priorityCheck(handle); error != 0) {
            return error;
        }
        self.priority = wanted == V4L2_PRIORITY_UNSET ? V4L2_PRIORITY_DEFAULT : v4l2_priority(wanted);
        return 0;
    }
    case VIDIOC_QUERYCTRL:
        return controls_.query(*static_cast<v4l2_queryctrl*>(arg));
    case VIDIOC_QUERY_EXT_CTRL:
        return controls_.queryExtended(*static_cast<v4l2_query_ext_ctrl*>(arg));
    case VIDIOC_QUERYMENU:
        return controls_.queryMenu(*static_cast<v4l2_querymenu*>(arg));
    case VIDIOC_G_CTRL:
        return controls_.get(*static_cast<v4l2_control*>(arg));
    case VIDIOC_S_CTRL:
        if (const int error = priorityCheck(handle); error != 0) {
            return error;
        }
        return controls_.set(*static_cast<v4l2_control*>(arg), listenerFor(handle));
    case VIDIOC_G_EXT_CTRLS:
        return controls_.getExtended(*static_cast<v4l2_ext_controls*>(arg));
    case VIDIOC_S_EXT_CTRLS:
        if (const int error = priorityCheck(handle); error != 0) {
            return error;
        }
        return controls_.setExtended(*static_cast<v4l2_ext_controls*>(arg), true, listenerFor(handle));
    case VIDIOC_TRY_EXT_CTRLS:
        return controls_.setExtended(*static_cast<v4l2_ext_controls*>(arg), false, nullptr);
    case VIDIOC_SUBSCRIBE_EVENT:
        return subscribe(self, *static_cast<v4l2_event_subscription*>(arg));
    case VIDIOC_UNSUBSCRIBE_EVENT:
        return unsubscribe(self, *static_cast<v4l2_event_subscription*>(arg));
    case VIDIOC_DQEVENT:
        return dequeueEvent(self, *static_cast<v4l2_event*>(arg));
    default:
        return ENOTTY;
    }
}

} // namespace lumar::vcam
