#include "capture/libcamera/libcamera_buffer.h"

#include <cerrno>
#include <cstring>
#include <map>
#include <string>

#include <fcntl.h>
#include <libcamera/formats.h>
#include <libcamera/framebuffer.h>

#include "core/error.h"

namespace lumar {

LibcameraBuffer::LibcameraBuffer(const libcamera::FrameBuffer& buffer, DmabufMapping mapping,
                                 const LibcameraLayout& layout)
    : mapping_(std::move(mapping))
{
    const auto& planes = buffer.planes();
    // The buffer's descriptors close with it: each distinct one is duplicated once.
    std::map<int, int> ownFd;
    for (const libcamera::FrameBuffer::Plane& plane : planes) {
        const int fd = plane.fd.get();
        if (ownFd.count(fd) != 0)
            continue;
        UniqueFd copy(::fcntl(fd, F_DUPFD_CLOEXEC, 0));
        if (!copy.valid())
            throw RuntimeError(std::string("libcamera: cannot duplicate a frame buffer's dmabuf: ") +
                               std::strerror(errno));
        ownFd[fd] = copy.get();
        dmabufs_.push_back(std::move(copy));
    }
    const size_t lumaBytes = layout.stride * size_t(layout.height);
    const int fd0 = ownFd.at(planes[0].fd.get());
    planes_[0] = {mapping_.plane(0), mapping_.planeLength(0), fd0, planes[0].offset};
    if (layout.format == libcamera::formats::NV12) {
        if (planes.size() >= 2) {
            planes_[1] = {mapping_.plane(1), mapping_.planeLength(1), ownFd.at(planes[1].fd.get()), planes[1].offset};
        } else {
            // One plane holding both: the chroma rows follow the luma rows.
            planes_[0].size = lumaBytes;
            planes_[1] = {mapping_.plane(0) + lumaBytes, mapping_.planeLength(0) - lumaBytes, fd0,
                          planes[0].offset + uint32_t(lumaBytes)};
        }
    }
    // CameraBuffer's formats are the YCbCr ones the renderer imports; an RGB buffer is none.
    drmFourcc_ = isPackedRgbLibcameraFormat(layout.format) ? 0 : layout.format.fourcc();
}

} // namespace lumar
