// The virtual camera's Motion-JPEG output: its test pattern compressed with libturbojpeg at
// the negotiated size (4:2:2, as UVC cameras send), once per distinct picture (the pattern
// repeats as its block travels), and the "corrupt frame" fault applied to a copy.
#pragma once

#include <cstddef>
#include <cstdint>
#include <map>
#include <memory>
#include <vector>

namespace lumar::vcam {

class MjpegFrames {
public:
    MjpegFrames();
    // The JPEG of pattern frame `frameIndex` at `width` x `height`; empty when encoding failed.
    // The reference stays valid until the size or quality changes.
    const std::vector<uint8_t>& frame(int64_t frameIndex, int width, int height, int quality);

private:
    struct HandleDeleter {
        void operator()(void* handle) const;
    };
    std::unique_ptr<void, HandleDeleter> handle_; // a tjhandle (compressor); null if unavailable
    int width_ = 0;
    int height_ = 0;
    int quality_ = 0;
    std::vector<uint8_t> rgb_;
    std::map<int, std::vector<uint8_t>> byBlockLeft_;
    std::vector<uint8_t> failed_;
};

// Writes a damaged copy of `jpeg` into `out` (capacity `capacity`) and returns its length: the
// first third kept, then garbage, then the end marker missing, so a decoder must reject it.
size_t corruptJpeg(const std::vector<uint8_t>& jpeg, uint8_t* out, size_t capacity);

} // namespace lumar::vcam
