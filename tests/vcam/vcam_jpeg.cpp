#include "vcam/vcam_jpeg.h"

#include <algorithm>
#include <cstring>

#include <turbojpeg.h>

#include "vcam/vcam_pattern.h"

namespace lumar::vcam {

void MjpegFrames::HandleDeleter::operator()(void* handle) const
{
    tjDestroy(static_cast<tjhandle>(handle));
}

MjpegFrames::MjpegFrames() : handle_(tjInitCompress()) {}

const std::vector<uint8_t>& MjpegFrames::frame(int64_t frameIndex, int width, int height, int quality)
{
    if (!handle_) {
        return failed_;
    }
    if (width != width_ || height != height_ || quality != quality_) {
        byBlockLeft_.clear();
        width_ = width;
        height_ = height;
        quality_ = quality;
        rgb_.resize(size_t(width) * size_t(height) * 3);
    }
    const int key = blockLeft(frameIndex, width);
    if (const auto found = byBlockLeft_.find(key); found != byBlockLeft_.end()) {
        return found->second;
    }
    drawPatternRgb(width, height, frameIndex, rgb_.data());
    unsigned char* jpeg = nullptr;
    unsigned long size = 0;
    if (tjCompress2(static_cast<tjhandle>(handle_.get()), rgb_.data(), width, width * 3, height, TJPF_RGB, &jpeg, &size,
                    TJSAMP_422, quality, TJFLAG_ACCURATEDCT) != 0) {
        tjFree(jpeg);
        return failed_;
    }
    std::vector<uint8_t>& stored = byBlockLeft_[key];
    stored.assign(jpeg, jpeg + size);
    tjFree(jpeg);
    return stored;
}

size_t corruptJpeg(const std::vector<uint8_t>& jpeg, uint8_t* out, size_t capacity)
{
    const size_t length = std::min(jpeg.size() / 2, capacity);
    const size_t kept = std::min(jpeg.size() / 3, length);
    std::memcpy(out, jpeg.data(), kept);
    // A run of restart markers and invalid codes where entropy-coded data should continue.
    for (size_t i = kept; i < length; ++i) {
        out[i] = (i % 2 == 0) ? 0xFF : uint8_t(0xD0 + (i / 2) % 8);
    }
    return length;
}

} // namespace lumar::vcam
