// One libcamera frame buffer as a CameraBuffer (core/ycbcr_image.h) frames can be lent: it
// owns the buffer's mapping and duplicates of its dmabufs, so a frame keeps the memory valid
// even after the source, its allocator and its FrameBuffer are gone, and describes the NV12
// (one plane or two) or YUYV planes in both. libcamera's pixel formats are DRM fourccs, so
// the layout's format is the buffer's DRM format as it is. Packed RGB buffers are never lent
// (the source converts them on the CPU): theirs describe plane 0 and no DRM format, so
// nothing can import one as a YCbCr frame.
#pragma once

#include <atomic>
#include <vector>

#include "capture/libcamera/dmabuf_mapping.h"
#include "capture/libcamera/libcamera_frame.h"
#include "core/unique_fd.h"
#include "core/ycbcr_image.h"

namespace libcamera {
class FrameBuffer;
}

namespace lumar {

class LibcameraBuffer final : public CameraBuffer {
public:
    // `mapping` is of `buffer` and holds a whole image of `layout` (checkMappedImage). Throws
    // RuntimeError when a dmabuf cannot be duplicated.
    LibcameraBuffer(const libcamera::FrameBuffer& buffer, DmabufMapping mapping, const LibcameraLayout& layout);

    [[nodiscard]] const DmabufMapping& mapping() const { return mapping_; }

    // Lending, as V4l2Buffer's (capture/v4l2/v4l2_buffer.h): the frames' handle calls
    // giveBack() when its last copy ends; returned() is the acquire side ThreadSanitizer checks.
    void lend() { returned_.store(false, std::memory_order_relaxed); }
    void giveBack() const { returned_.store(true, std::memory_order_release); }
    [[nodiscard]] bool returned() const { return returned_.load(std::memory_order_acquire); }

private:
    DmabufMapping mapping_;
    std::vector<UniqueFd> dmabufs_; // one per distinct dmabuf of the buffer
    mutable std::atomic<bool> returned_{false};
};

} // namespace lumar
