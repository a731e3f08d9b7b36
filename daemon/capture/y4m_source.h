// File playback from a YUV4MPEG2 (.y4m) video, the format ffmpeg and `lumar render` write.
// Frames are converted with BT.601 in the range the header states (XCOLORRANGE, limited
// when absent, as ffmpeg writes); the frame rate comes from the header's F field.
#pragma once

#include <fstream>
#include <string>
#include <vector>

#include "capture/capture_source.h"
#include "capture/colour_conversion.h"
#include "capture/y4m_header.h"

namespace lumar {

class Y4mSource final : public CaptureSource {
public:
    // Opens config.path and checks its header and that its first frame is complete. Uses
    // config.fps when the header has no F field; plays again from the start when
    // config.loop. Throws InputError "FILE: what is wrong".
    explicit Y4mSource(const CameraConfig& config);

    bool next(Frame& frame) override; // throws InputError for a malformed or truncated frame
    [[nodiscard]] int width() const override { return header_.width; }
    [[nodiscard]] int height() const override { return header_.height; }
    [[nodiscard]] double fps() const override { return fps_; }
    [[nodiscard]] bool fullRange() const { return header_.fullRange; }

private:
    // Reads one "FRAME[ params]\n" line. Returns false at a clean end of file.
    bool readFrameMarker();
    [[nodiscard]] std::string where() const; // "FILE: frame N"

    std::string fileName_;
    std::ifstream file_;
    Y4mHeader header_;
    double fps_ = 0.0;
    bool loop_ = true;
    std::streampos firstFrame_;
    uint64_t framesInFile_ = 0; // frames read since the last (re)start of the file
    uint64_t sequence_ = 0;
    std::vector<uint8_t> planes_;
    YCbCrToRgb converter_;
};

} // namespace lumar
