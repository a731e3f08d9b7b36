// One open virtual V4L2 capture device: the state machine behind the ioctl ABI (formats,
// frame rate, MMAP buffers, streaming) and the frame clock that fills queued buffers.
// Not thread-safe by itself: the interposers serialise every call with one lock.
#pragma once

#include <cstddef>
#include <cstdint>
#include <deque>
#include <vector>

#include <linux/videodev2.h>
#include <sys/types.h>

#include "vcam/vcam_settings.h"

namespace lumar::vcam {

class VirtualDevice {
public:
    VirtualDevice(Settings settings, bool nonBlocking);
    ~VirtualDevice();
    VirtualDevice(const VirtualDevice&) = delete;
    VirtualDevice& operator=(const VirtualDevice&) = delete;

    // Handles one V4L2 ioctl at time `nowNs` (CLOCK_MONOTONIC). Returns 0 or an errno.
    int ioctl(unsigned long request, void* arg, int64_t nowNs);
    // poll() events now: POLLIN|POLLRDNORM when a filled buffer waits, POLLERR when not
    // streaming, when no buffer is queued, or once unplugged (with POLLHUP).
    short pollEvents(int64_t nowNs);
    // When the next frame falls due (INT64_MAX: none will), for waits in poll/select/DQBUF.
    [[nodiscard]] int64_t nextFrameDueNs() const;
    // The memfd and its offset to map for mmap(length, offset) of this device; -1 and an
    // errno in `error` when the range is not one buffer.
    int memfdForMapping(size_t length, off_t offset, int& error) const;

    [[nodiscard]] bool nonBlocking() const { return nonBlocking_; }
    [[nodiscard]] bool streaming() const { return streaming_; }

private:
    enum class BufferState { Dequeued, Queued, Done };
    struct Buffer {
        BufferState state = BufferState::Dequeued;
        uint32_t sequence = 0;
        int64_t timestampNs = 0;
        uint32_t bytesUsed = 0;
    };

    // Produces every frame due by `nowNs`: into the oldest queued buffer, or dropped when
    // none is queued (as a driver does), or dropped/shortened/stalled/unplugged by a fault.
    void advance(int64_t nowNs);
    [[nodiscard]] bool supportedFormat(uint32_t pixelFormat) const;
    [[nodiscard]] int64_t frameDueNs(int64_t frameIndex) const;
    void setFormat(v4l2_pix_format& format) const;
    void describeBuffer(uint32_t index, v4l2_buffer& out) const;
    int requestBuffers(v4l2_requestbuffers& request);
    void releaseBuffers();
    void stopStreaming();

    int queryCapability(v4l2_capability& capability) const;
    int enumerateFormat(v4l2_fmtdesc& description) const;
    int enumerateFrameSize(v4l2_frmsizeenum& size) const;
    int enumerateFrameInterval(v4l2_frmivalenum& interval) const;
    int setOrTryFormat(v4l2_format& format, bool apply);
    int frameRateParameters(v4l2_streamparm& parameters, bool apply);
    int queueBuffer(v4l2_buffer& buffer);
    int dequeueBuffer(v4l2_buffer& buffer);

    Settings settings_;
    bool nonBlocking_;
    v4l2_pix_format format_{};
    v4l2_fract timePerFrame_{1, 30};
    // The buffers live in one memfd, buffer i at offset i * bufferStride_ (its mmap cookie).
    int memfd_ = -1;
    uint8_t* memory_ = nullptr;
    size_t memorySize_ = 0;
    size_t bufferStride_ = 0;
    std::vector<Buffer> buffers_;
    std::deque<uint32_t> queued_;
    std::deque<uint32_t> done_;
    bool streaming_ = false;
    bool unplugged_ = false;
    int64_t streamStartNs_ = 0;
    int64_t frameIndex_ = 0; // the next frame to fall due; equals its V4L2 sequence number
};

} // namespace lumar::vcam
