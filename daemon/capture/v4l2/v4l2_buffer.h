// One V4L2 MMAP capture buffer as a CameraBuffer (core/ycbcr_image.h) that frames can be lent:
// it owns the buffer's mapping and, where VIDIOC_EXPBUF worked, its dmabuf, and describes the
// NV12 or YUYV planes in both. Made once per buffer when the stream starts.
#pragma once

#include <atomic>
#include <cstddef>
#include <cstdint>
#include <string>

#include "capture/v4l2/mapped_region.h"
#include "core/unique_fd.h"
#include "core/ycbcr_image.h"

namespace lumar {

class V4l2Buffer final : public CameraBuffer {
public:
    // `mapping` holds the whole buffer; `dmabuf` is its export (invalid: not exported).
    // `pixelFormat` is the negotiated V4L2 fourcc; planes are described for NV12 (Y, then the
    // interleaved chroma after `height` rows) and YUYV (one plane) only.
    V4l2Buffer(MappedRegion mapping, UniqueFd dmabuf, uint32_t pixelFormat, int height, size_t bytesPerLine);

    [[nodiscard]] const uint8_t* data() const { return mapping_.data(); }
    [[nodiscard]] size_t size() const { return mapping_.size(); }

    // Lending (V4l2Source::lendBuffer): the frames' handle on the buffer calls giveBack() when
    // its last copy ends, and the source queues the buffer again once returned() says so. A
    // release/acquire pair on the buffer's own flag: the frames' last reads happen before the
    // driver may write the buffer again, in a way ThreadSanitizer can check (the former
    // use_count() test with an acquire fence was correct C++, but TSan cannot model fences
    // and GCC refuses to build one with -fsanitize=thread).
    void lend() { returned_.store(false, std::memory_order_relaxed); }
    void giveBack() const { returned_.store(true, std::memory_order_release); }
    [[nodiscard]] bool returned() const { return returned_.load(std::memory_order_acquire); }

private:
    MappedRegion mapping_;
    UniqueFd dmabuf_;
    mutable std::atomic<bool> returned_{false};
};

// The DRM fourcc of a V4L2 pixel format the renderer can import (DRM_FORMAT_NV12,
// DRM_FORMAT_YUYV); 0 for any other.
uint32_t drmFourccOfV4l2(uint32_t pixelFormat);

// VIDIOC_EXPBUF of MMAP buffer `index` (read-only, close-on-exec). Invalid with `error` set
// when the driver cannot export (ENOTTY on drivers without dmabuf support, EINVAL).
UniqueFd exportV4l2Buffer(int deviceFd, uint32_t index, std::string& error);

} // namespace lumar
