// Headless outputs: a PNG still (the last frame written) or a Y4M video (every frame,
// 4:2:0 full-range BT.601, "C420jpeg"), chosen by the file extension.
#pragma once

#include <filesystem>
#include <memory>

#include "core/image.h"

namespace lumar {

class FrameWriter {
public:
    virtual ~FrameWriter() = default;
    // `rgb` has 3 channels. Throws RuntimeError on an I/O failure.
    virtual void write(const Image8& rgb) = 0;
    // Flushes and closes; also done by the destructor, which cannot report errors.
    virtual void finish() = 0;
};

// Throws InputError for an extension other than .png / .y4m.
std::unique_ptr<FrameWriter> openFrameWriter(const std::filesystem::path& file, double fps);

// Single images. Throw RuntimeError / InputError naming the file.
void writePng(const std::filesystem::path& file, const Image8& image);
Image8 readImage(const std::filesystem::path& file, int channels); // PNG/JPEG/..., sRGB 8-bit

} // namespace lumar
