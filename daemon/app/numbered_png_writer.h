// An image-sequence output: "--out frames/f_%04d.png" writes every frame as its own PNG,
// numbered from 0 with the printf-style pattern (exactly one integer conversion).
#pragma once

#include <filesystem>
#include <string>

#include "output/frame_writer.h"

namespace lumar {

class NumberedPngWriter final : public FrameWriter {
public:
    // Throws InputError when the pattern is not "...%d..." (with optional flags and width).
    explicit NumberedPngWriter(std::string pattern);
    void write(const Image8& rgb) override;
    void finish() override {}

    static bool isPattern(const std::string& path) { return path.find('%') != std::string::npos; }

private:
    std::string pattern_;
    long next_ = 0;
};

} // namespace lumar
