// Writes frames as a YUV4MPEG2 video: 4:2:0 full-range BT.601 ("C420jpeg
// XCOLORRANGE=FULL"), which ffmpeg, mpv and lumar's own Y4M source read back.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "output/c_file.h"
#include "output/frame_writer.h"

namespace lumar {

// The F field's value for `fps`: "30:1", "30000:1001" for NTSC-style rates, otherwise the
// nearest fraction with denominator 1000 (reduced). Throws InputError for fps <= 0.
std::string y4mFrameRate(double fps);

class Y4mWriter final : public FrameWriter {
public:
    // Opens the file now (so a bad path fails before any rendering); the header is written
    // with the first frame, whose size every later frame must share.
    Y4mWriter(const std::filesystem::path& file, double fps);
    ~Y4mWriter() override;

    // Throws InputError for an odd width or height (4:2:0) or a change of size,
    // RuntimeError for an I/O failure.
    void write(const Image8& rgb) override;
    void finish() override;

private:
    std::filesystem::path path_;
    std::string frameRate_;
    CFile file_;
    int width_ = 0;
    int height_ = 0;
    std::vector<uint8_t> planes_; // Y, Cb, Cr of one frame, reused
};

} // namespace lumar
