// Read access to a libcamera FrameBuffer's planes: each distinct dmabuf is mmap()ed once
// (planes of one buffer often share a dmabuf at different offsets) and unmapped when the
// mapping is destroyed. A source maps each of its buffers once and keeps the mapping for the
// stream's life, instead of mapping per frame.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "capture/v4l2/mapped_region.h"

namespace libcamera {
class FrameBuffer;
}

namespace lumar {

class DmabufMapping {
public:
    // Maps every plane of `buffer` read-only. Throws RuntimeError when a plane has no valid
    // file descriptor or offset, or mmap fails.
    explicit DmabufMapping(const libcamera::FrameBuffer& buffer);

    [[nodiscard]] size_t planeCount() const { return planes_.size(); }
    [[nodiscard]] const uint8_t* plane(size_t index) const { return planes_[index].data; }
    [[nodiscard]] size_t planeLength(size_t index) const { return planes_[index].length; }

private:
    struct Plane {
        const uint8_t* data = nullptr;
        size_t length = 0;
    };
    std::vector<MappedRegion> regions_; // one per distinct dmabuf
    std::vector<Plane> planes_;         // point into regions_
};

} // namespace lumar
