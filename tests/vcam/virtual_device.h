// One virtual V4L2 capture device: the state machine behind the ioctl ABI (formats, frame
// rate, MMAP buffers, streaming, controls, events, priorities) and the frame clock that fills
// queued buffers. Like a kernel device node it is shared by every open file handle: format,
// buffers and controls belong to the device, events and priority to each handle, and the
// buffers to the handle that allocated them (others get EBUSY).
// Not thread-safe by itself: the interposers serialise every call with one lock.
#pragma once

#include <cstddef>
#include <cstdint>
#include <deque>
#include <map>
#include <vector>

#include <linux/videodev2.h>
#include <sys/types.h>

#include "vcam/vcam_controls.h"
#include "vcam/vcam_jpeg.h"
#include "vcam/vcam_settings.h"

namespace lumar::vcam {

class VirtualDevice {
public:
    explicit VirtualDevice(Settings settings);
    ~VirtualDevice();
    VirtualDevice(const VirtualDevice&) = delete;
    VirtualDevice& operator=(const VirtualDevice&) = delete;

    // A new file handle on the device, and its end (which frees its buffers if it owns them).
    int openHandle();
    void closeHandle(int handle);
    [[nodiscard]] bool hasHandles() const { return !handles_.empty(); }

    // Handles one V4L2 ioctl from `handle` at time `nowNs` (CLOCK_MONOTONIC). Returns 0 or an errno.
    int ioctl(int handle, unsigned long request, void* arg, int64_t nowNs);
    // poll() events now for `handle`: POLLPRI when an event waits; for `requested` POLLIN,
    // POLLIN|POLLRDNORM when a filled buffer waits, POLLERR when not streaming or no buffer is
    // queued; POLLERR|POLLHUP once unplugged.
    short pollEvents(int handle, short requested, int64_t nowNs);
    // When the next frame falls due (INT64_MAX: none will), for waits in poll/select/DQBUF.
    [[nodiscard]] int64_t nextFrameDueNs() const;
    // The memfd to map for mmap(length, offset) of this device (each buffer has its own memfd,
    // mapped from 0; `offset` is its cookie); -1 and an errno in `error` when it is not a buffer.
    int memfdForMapping(size_t length, off_t offset, int& error) const;

    [[nodiscard]] bool streaming() const { return streaming_; }
    [[nodiscard]] const Settings& settings() const { return settings_; }

private:
    enum class BufferState { Dequeued, Queued, Done };
    struct Buffer {
        BufferState state = BufferState::Dequeued;
        uint32_t sequence = 0;
        int64_t timestampNs = 0;
        uint32_t bytesUsed = 0;
        int memfd = -1;
        uint8_t* memory = nullptr;
        size_t length = 0; // page-rounded
        size_t offset = 0; // the mmap offset cookie: the lengths of the buffers before it
    };
    struct Handle {
        v4l2_priority priority = V4L2_PRIORITY_DEFAULT;
        std::vector<v4l2_event_subscription> subscriptions;
        std::deque<v4l2_event> events;
        uint32_t eventSequence = 0;
    };
    struct Size {
        uint32_t width;
        uint32_t height;
    };

    // Produces every frame due by `nowNs`: into the oldest queued buffer, or dropped when
    // none is queued (as a driver does), or dropped/shortened/corrupted/stalled/unplugged by a fault.
    void advance(int64_t nowNs);
    void fillBuffer(Buffer& buffer, int64_t frameIndex);
    [[nodiscard]] bool supportedFormat(uint32_t pixelFormat) const;
    [[nodiscard]] bool supportedSize(uint32_t width, uint32_t height) const;
    [[nodiscard]] int64_t frameDueNs(int64_t frameIndex) const;
    // LUMAR_VCAM_PACED=1: when the next frame may come (INT64_MAX while the reader holds a
    // frame not taken yet or no buffer is queued).
    [[nodiscard]] int64_t pacedDueNs() const;
    void setFormat(v4l2_pix_format& format) const;
    void describeBuffer(uint32_t index, v4l2_buffer& out) const;
    int requestBuffers(int handle, v4l2_requestbuffers& request);
    int createBuffers(int handle, v4l2_create_buffers& request);
    int allocate(uint32_t count, size_t size);
    void releaseBuffers();
    void stopStreaming();
    // Whether a handle other than `handle` owns the buffers (V4L2: EBUSY).
    [[nodiscard]] bool busyFor(int handle) const;
    // The kernel's priority check for ioctls that change state: EBUSY when another handle
    // holds a higher priority.
    [[nodiscard]] int priorityCheck(int handle) const;
    [[nodiscard]] v4l2_priority maxPriority() const;

    int queryCapability(v4l2_capability& capability) const;
    int enumerateFormat(v4l2_fmtdesc& description) const;
    int enumerateFrameSize(v4l2_frmsizeenum& size) const;
    int enumerateFrameInterval(v4l2_frmivalenum& interval) const;
    int setOrTryFormat(int handle, v4l2_format& format, bool apply);
    int frameRateParameters(v4l2_streamparm& parameters, bool apply);
    int queueBuffer(int handle, v4l2_buffer& buffer);
    int dequeueBuffer(int handle, v4l2_buffer& buffer);
    int exportBuffer(int handle, v4l2_exportbuffer& request);
    int subscribe(Handle& handle, const v4l2_event_subscription& subscription);
    int unsubscribe(Handle& handle, const v4l2_event_subscription& subscription);
    int dequeueEvent(Handle& handle, v4l2_event& event);
    void raiseEvent(Handle& handle, v4l2_event event);
    // Queues a control event on each handle subscribed to `id` (the changer itself only with
    // V4L2_EVENT_SUB_FL_ALLOW_FEEDBACK).
    void raiseControlEvent(int changer, const v4l2_event_ctrl& state, uint32_t id, uint32_t changes);
    ControlSet::ChangeListener listenerFor(int handle);

    Settings settings_;
    std::vector<Size> sizes_;
    v4l2_pix_format format_{};
    v4l2_fract timePerFrame_{1, 30};
    std::vector<Buffer> buffers_;
    int owner_ = -1; // the handle that allocated the buffers
    std::deque<uint32_t> queued_;
    std::deque<uint32_t> done_;
    bool streaming_ = false;
    bool unplugged_ = false;
    bool sourceChanged_ = false; // the input changed size: no frames until the next STREAMON
    int64_t streamStartNs_ = 0;
    int64_t pacedNotBeforeNs_ = 0; // LUMAR_VCAM_PACED: one period after the last frame
    int64_t frameIndex_ = 0;       // the next frame to fall due; equals its V4L2 sequence number
    int64_t framesProduced_ = 0;   // over the device's life, for the source-change fault
    ControlSet controls_;
    MjpegFrames mjpeg_;
    std::map<int, Handle> handles_;
    int nextHandle_ = 1;
};

} // namespace lumar::vcam
