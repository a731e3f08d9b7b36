// The stream header of a YUV4MPEG2 (.y4m) file: "YUV4MPEG2 W1280 H720 F30:1 Ip A1:1 C420jpeg
// XCOLORRANGE=FULL", one line of space-separated fields, each named by its first letter.
#pragma once

#include <cstddef>
#include <string>
#include <string_view>

namespace lumar {

inline constexpr int kY4mMaxDimension = 16384;
// Frame rates accepted from the F field: one frame in ten seconds to a thousand a second.
inline constexpr double kY4mMinFps = 0.1;
inline constexpr double kY4mMaxFps = 1000.0;

enum class Y4mChroma { Yuv420, Yuv422, Yuv444, Mono };

struct Y4mHeader {
    int width = 0;
    int height = 0;
    int fpsNumerator = 0; // 0 when the header has no F field
    int fpsDenominator = 0;
    Y4mChroma chroma = Y4mChroma::Yuv420; // C420jpeg when the header has no C field
    bool fullRange = false;               // XCOLORRANGE=FULL; LIMITED is the default

    [[nodiscard]] int chromaWidth() const; // 0 for monochrome
    [[nodiscard]] int chromaHeight() const;
    [[nodiscard]] size_t frameBytes() const; // all planes of one frame
};

// Parses the header line without its trailing newline. Throws InputError "FILE: ..." for a
// wrong magic, a missing or malformed W/H, sizes outside 1..16384, odd sizes for 4:2:0, a
// frame rate outside 0.1..1000 fps or an unsupported colour space (anything but 8-bit 4:2:0, 4:2:2, 4:4:4
// and mono).
Y4mHeader parseY4mHeader(std::string_view line, const std::string& fileName);

} // namespace lumar
