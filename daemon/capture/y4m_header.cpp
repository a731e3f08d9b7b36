#include "capture/y4m_header.h"

#include <charconv>
#include <vector>

#include "core/error.h"

namespace lumar {
namespace {

constexpr std::string_view kMagic = "YUV4MPEG2";

std::vector<std::string_view> splitFields(std::string_view line)
{
    std::vector<std::string_view> fields;
    size_t pos = 0;
    while (pos < line.size()) {
        const size_t end = std::min(line.find(' ', pos), line.size());
        if (end > pos) {
            fields.push_back(line.substr(pos, end - pos));
        }
        pos = end + 1;
    }
    return fields;
}

bool parseInt(std::string_view text, int& out)
{
    if (text.empty()) {
        return false;
    }
    const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), out);
    return ec == std::errc() && end == text.data() + text.size();
}

// "N:D" with both positive.
bool parseRatio(std::string_view text, int& numerator, int& denominator)
{
    const size_t colon = text.find(':');
    return colon != std::string_view::npos && parseInt(text.substr(0, colon), numerator) &&
           parseInt(text.substr(colon + 1), denominator) && numerator > 0 && denominator > 0;
}

bool parseChroma(std::string_view text, Y4mChroma& out)
{
    if (text == "420jpeg" || text == "420paldv" || text == "420mpeg2" || text == "420") {
        out = Y4mChroma::Yuv420;
    } else if (text == "422") {
        out = Y4mChroma::Yuv422;
    } else if (text == "444") {
        out = Y4mChroma::Yuv444;
    } else if (text == "mono") {
        out = Y4mChroma::Mono;
    } else {
        return false;
    }
    return true;
}

} // namespace

int Y4mHeader::chromaWidth() const
{
    switch (chroma) {
    case Y4mChroma::Yuv420:
    case Y4mChroma::Yuv422:
        return (width + 1) / 2;
    case Y4mChroma::Yuv444:
        return width;
    case Y4mChroma::Mono:
        return 0;
    }
    return 0;
}

int Y4mHeader::chromaHeight() const
{
    switch (chroma) {
    case Y4mChroma::Yuv420:
        return (height + 1) / 2;
    case Y4mChroma::Yuv422:
    case Y4mChroma::Yuv444:
        return height;
    case Y4mChroma::Mono:
        return 0;
    }
    return 0;
}

size_t Y4mHeader::frameBytes() const
{
    return size_t(width) * size_t(height) + 2 * size_t(chromaWidth()) * size_t(chromaHeight());
}

Y4mHeader parseY4mHeader(std::string_view line, const std::string& fileName)
{
    const auto fail = [&](const std::string& what) { throw InputError(fileName + ": " + what); };

    const std::vector<std::string_view> fields = splitFields(line);
    if (fields.empty() || fields.front() != kMagic) {
        fail("not a YUV4MPEG2 file (the header must start with \"YUV4MPEG2 \")");
    }
    Y4mHeader header;
    bool haveWidth = false;
    bool haveHeight = false;
    for (size_t i = 1; i < fields.size(); ++i) {
        const std::string_view field = fields[i];
        const char tag = field.front();
        const std::string_view value = field.substr(1);
        switch (tag) {
        case 'W':
            if (!parseInt(value, header.width)) {
                fail("bad width field '" + std::string(field) + "'");
            }
            haveWidth = true;
            break;
        case 'H':
            if (!parseInt(value, header.height)) {
                fail("bad height field '" + std::string(field) + "'");
            }
            haveHeight = true;
            break;
        case 'F':
            if (!parseRatio(value, header.fpsNumerator, header.fpsDenominator)) {
                fail("bad frame rate field '" + std::string(field) + "' (expected F<num>:<den>)");
            }
            break;
        case 'C':
            if (!parseChroma(value, header.chroma)) {
                fail("unsupported colour space '" + std::string(field) +
                     "' (8-bit C420jpeg, C420paldv, C420mpeg2, C420, C422, C444 or Cmono only)");
            }
            break;
        case 'X':
            if (value == "COLORRANGE=FULL") {
                header.fullRange = true;
            } else if (value == "COLORRANGE=LIMITED") {
                header.fullRange = false;
            }
            break;
        default:
            // I (interlacing) and A (pixel aspect) do not change how frames decode; other
            // letters are reserved by the format and skipped, as other readers do.
            break;
        }
    }
    if (!haveWidth || !haveHeight) {
        fail("the header has no W (width) or H (height) field");
    }
    // A rate outside this range is not a video (issue 16: F1:1000 made `lumar run` wait a
    // thousand seconds per frame, and F1:2147483647 overflowed the frame timestamps).
    if (header.fpsNumerator > 0) {
        const double fps = double(header.fpsNumerator) / double(header.fpsDenominator);
        if (!(fps >= kY4mMinFps && fps <= kY4mMaxFps)) {
            fail("frame rate " + std::to_string(header.fpsNumerator) + ":" + std::to_string(header.fpsDenominator) +
                 " is outside 0.1..1000 frames per second");
        }
    }
    const auto validDimension = [](int v) { return v >= 1 && v <= kY4mMaxDimension; };
    if (!validDimension(header.width) || !validDimension(header.height)) {
        fail("frame size " + std::to_string(header.width) + "x" + std::to_string(header.height) +
             " is outside 1..16384");
    }
    if (header.chroma == Y4mChroma::Yuv420 && (header.width % 2 != 0 || header.height % 2 != 0)) {
        fail("4:2:0 frames need an even width and height, got " + std::to_string(header.width) + "x" +
             std::to_string(header.height));
    }
    if (header.chroma == Y4mChroma::Yuv422 && header.width % 2 != 0) {
        fail("4:2:2 frames need an even width, got " + std::to_string(header.width));
    }
    return header;
}

} // namespace lumar
