// The .png output: keeps the most recent frame and writes it as one PNG at finish(), so a
// run or render leaves the last picture it made.
#pragma once

#include <filesystem>

#include "output/frame_writer.h"

namespace lumar {

class PngStillWriter final : public FrameWriter {
public:
    explicit PngStillWriter(std::filesystem::path file);
    ~PngStillWriter() override;

    void write(const Image8& rgb) override; // copies into a reused buffer
    void finish() override;                 // writes the PNG; RuntimeError on failure

private:
    std::filesystem::path path_;
    Image8 last_;
    bool finished_ = false;
};

} // namespace lumar
