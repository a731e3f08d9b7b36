#include "capture/v4l2/v4l2_buffer.h"

#include <cstring>

#include <fcntl.h>
#include <libdrm/drm_fourcc.h>
#include <linux/videodev2.h>

#include "capture/v4l2/v4l2_ioctl.h"

namespace lumar {

// The two fourcc spaces agree on these (both spell 'NV12', 'YUYV'); the constants say which.
static_assert(DRM_FORMAT_NV12 == V4L2_PIX_FMT_NV12 && DRM_FORMAT_YUYV == V4L2_PIX_FMT_YUYV);

V4l2Buffer::V4l2Buffer(MappedRegion mapping, UniqueFd dmabuf, uint32_t pixelFormat, int height, size_t bytesPerLine)
    : mapping_(std::move(mapping)), dmabuf_(std::move(dmabuf))
{
    const size_t lumaBytes = bytesPerLine * size_t(height);
    planes_[0] = {mapping_.data(), mapping_.size(), dmabuf_.get(), 0};
    if (pixelFormat == V4L2_PIX_FMT_NV12 && mapping_.size() >= lumaBytes) {
        // Single-planar NV12: the chroma rows follow the luma rows in the same buffer.
        planes_[0].size = lumaBytes;
        planes_[1] = {mapping_.data() + lumaBytes, mapping_.size() - lumaBytes, dmabuf_.get(), uint32_t(lumaBytes)};
    }
    drmFourcc_ = drmFourccOfV4l2(pixelFormat);
}

uint32_t drmFourccOfV4l2(uint32_t pixelFormat)
{
    switch (pixelFormat) {
    case V4L2_PIX_FMT_NV12:
        return DRM_FORMAT_NV12;
    case V4L2_PIX_FMT_YUYV:
        return DRM_FORMAT_YUYV;
    default:
        return 0;
    }
}

UniqueFd exportV4l2Buffer(int deviceFd, uint32_t index, std::string& error)
{
    v4l2_exportbuffer request{};
    request.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
    request.index = index;
    request.plane = 0;
    request.flags = O_RDONLY | O_CLOEXEC;
    if (const int code = v4l2Ioctl(deviceFd, VIDIOC_EXPBUF, &request); code != 0) {
        error = std::string("VIDIOC_EXPBUF: ") + std::strerror(code);
        return UniqueFd();
    }
    return UniqueFd(request.fd);
}

} // namespace lumar
