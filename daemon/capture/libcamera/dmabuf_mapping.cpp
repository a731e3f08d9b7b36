#include "capture/libcamera/dmabuf_mapping.h"

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <map>
#include <string>

#include <libcamera/framebuffer.h>
#include <sys/mman.h>

#include "core/error.h"

namespace lumar {

DmabufMapping::DmabufMapping(const libcamera::FrameBuffer& buffer)
{
    const auto& planes = buffer.planes();
    // The extent each dmabuf must be mapped to: the furthest end of any plane it holds.
    // Mapping from offset 0 keeps mmap's page alignment rule out of the plane offsets.
    std::map<int, size_t> extentOfFd;
    for (const libcamera::FrameBuffer::Plane& plane : planes) {
        if (!plane.fd.isValid() || plane.offset == libcamera::FrameBuffer::Plane::kInvalidOffset) {
            throw RuntimeError("libcamera: a frame buffer plane has no valid dmabuf or offset");
        }
        size_t& extent = extentOfFd[plane.fd.get()];
        extent = std::max(extent, size_t(plane.offset) + plane.length);
    }
    std::map<int, const uint8_t*> baseOfFd;
    regions_.reserve(extentOfFd.size());
    for (const auto& [fd, extent] : extentOfFd) {
        void* address = ::mmap(nullptr, extent, PROT_READ, MAP_SHARED, fd, 0);
        if (address == MAP_FAILED) {
            throw RuntimeError(std::string("libcamera: mmap of a frame buffer (") + std::to_string(extent) +
                               " bytes) failed: " + std::strerror(errno));
        }
        regions_.emplace_back(address, extent);
        baseOfFd[fd] = regions_.back().data();
    }
    planes_.reserve(planes.size());
    for (const libcamera::FrameBuffer::Plane& plane : planes) {
        planes_.push_back({baseOfFd[plane.fd.get()] + plane.offset, plane.length});
    }
}

} // namespace lumar
