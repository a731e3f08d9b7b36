// Copies a finished frame from GL into a CPU image, row 0 at the top.
#pragma once

#include <cstdint>
#include <vector>

#include "core/image.h"
#include "gles_renderer/gl/gl_object.h"

namespace lumar {

class FrameReadback {
public:
    // `framebuffer` is the single-sampled RGBA8 framebuffer frames are read from; it holds
    // image row y in row y, so no flip is needed.
    FrameReadback(GLuint framebuffer, int width, int height);

    // Reshapes `rgb` to width x height x 3 (no allocation when it already is) and fills it.
    void read(Image8& rgb);

private:
    GLuint framebuffer_;
    int width_;
    int height_;
    // GLES guarantees only RGBA reads; RGB is used where the implementation offers it.
    bool readsRgbDirectly_ = false;
    // Reused staging for RGBA reads, kReadbackRowsPerRead rows of it: read and repacked a strip at a
    // time, not as a whole frame (3.5 MB at 1280x720 that stayed resident, issue 18).
    std::vector<uint8_t> rgba_;
};

// Rows of RGBA staging FrameReadback holds (0.3 MB at 1280 wide, within a core's L2).
inline constexpr int kReadbackRowsPerRead = 64;

} // namespace lumar
