#include "gles_renderer/assets/radiance_hdr_check.h"

#include <algorithm>
#include <cstdlib>
#include <string>

#include "core/error.h"

namespace lumar {
namespace {

// Byte reader with stb_image's memory semantics: reading past the end yields 0 (recorded
// here as `overran`), and "at end" means no byte is left.
class ByteCursor {
public:
    explicit ByteCursor(std::span<const uint8_t> bytes) : bytes_(bytes) {}

    uint8_t get8()
    {
        if (position_ < bytes_.size()) {
            return bytes_[position_++];
        }
        overran_ = true;
        return 0;
    }
    [[nodiscard]] bool atEnd() const { return position_ >= bytes_.size(); }
    [[nodiscard]] bool overran() const { return overran_; }
    [[nodiscard]] size_t remaining() const { return bytes_.size() - std::min(position_, bytes_.size()); }
    void skip(size_t n)
    {
        if (n > remaining()) {
            overran_ = true;
            position_ = bytes_.size();
        } else {
            position_ += n;
        }
    }

private:
    std::span<const uint8_t> bytes_;
    size_t position_ = 0;
    bool overran_ = false;
};

// stbi__hdr_gettoken: one header line (at most 1023 characters kept), read as a C string.
std::string headerToken(ByteCursor& cursor)
{
    constexpr size_t kMaxToken = 1023;
    std::string token;
    char c = char(cursor.get8());
    while (!cursor.atEnd() && c != '\n') {
        token.push_back(c);
        if (token.size() == kMaxToken) {
            while (!cursor.atEnd() && cursor.get8() != '\n') {
            }
            break;
        }
        c = char(cursor.get8());
    }
    return token.substr(0, token.find('\0'));
}

RadianceImageSize parseHeader(ByteCursor& cursor)
{
    const std::string magic = headerToken(cursor);
    if (magic != "#?RADIANCE" && magic != "#?RGBE") {
        throw InputError("not a Radiance .hdr image");
    }
    bool rgbe = false;
    for (std::string token = headerToken(cursor); !token.empty(); token = headerToken(cursor)) {
        rgbe = rgbe || token == "FORMAT=32-bit_rle_rgbe";
        if (cursor.atEnd()) {
            throw InputError("the .hdr header is not terminated by an empty line");
        }
    }
    if (!rgbe) {
        throw InputError("the .hdr header has no FORMAT=32-bit_rle_rgbe line");
    }
    const std::string resolution = headerToken(cursor);
    const char* text = resolution.c_str();
    if (resolution.compare(0, 3, "-Y ") != 0) {
        throw InputError("unsupported .hdr layout '" + resolution + "' (only -Y H +X W)");
    }
    char* end = nullptr;
    const long height = std::strtol(text + 3, &end, 10);
    while (*end == ' ') {
        ++end;
    }
    if (std::string(end).compare(0, 3, "+X ") != 0) {
        throw InputError("unsupported .hdr layout '" + resolution + "' (only -Y H +X W)");
    }
    const long width = std::strtol(end + 3, nullptr, 10);
    if (width < 1 || height < 1 || width > 1L << 24 || height > 1L << 24) {
        throw InputError("invalid .hdr size " + std::to_string(width) + "x" + std::to_string(height));
    }
    return {int(width), int(height)};
}

// Bytes of flat (uncompressed) RGBE data for `pixels` pixels, or overran.
void skipFlatPixels(ByteCursor& cursor, uint64_t pixels)
{
    if (pixels * 4 > cursor.remaining()) {
        cursor.skip(cursor.remaining() + 1);
    } else {
        cursor.skip(size_t(pixels * 4));
    }
}

} // namespace

RadianceImageSize checkRadianceStream(std::span<const uint8_t> bytes)
{
    ByteCursor cursor(bytes);
    const RadianceImageSize size = parseHeader(cursor);
    const uint64_t pixels = uint64_t(size.width) * uint64_t(size.height);

    // stb_image reads flat data for widths it cannot run-length encode.
    if (size.width < 8 || size.width >= 32768) {
        skipFlatPixels(cursor, pixels);
    } else {
        for (int row = 0; row < size.height && !cursor.overran(); ++row) {
            const uint8_t c1 = cursor.get8(), c2 = cursor.get8(), lengthHigh = cursor.get8();
            if (c1 != 2 || c2 != 2 || (lengthHigh & 0x80) != 0) {
                // Not an RLE scanline: stb takes these bytes as pixel 0 and reads every
                // remaining pixel of the image flat from here on.
                cursor.get8();
                skipFlatPixels(cursor, pixels - 1);
                break;
            }
            const int scanlineLength = int(lengthHigh) << 8 | cursor.get8();
            if (scanlineLength != size.width) {
                throw InputError("corrupt .hdr: scanline " + std::to_string(row) + " has length " +
                                 std::to_string(scanlineLength) + ", expected " + std::to_string(size.width));
            }
            for (int component = 0; component < 4 && !cursor.overran(); ++component) {
                int filled = 0;
                while (filled < size.width && !cursor.overran()) {
                    int count = cursor.get8();
                    const bool run = count > 128;
                    if (run) {
                        count -= 128;
                    }
                    if (count == 0 || count > size.width - filled) {
                        throw InputError("corrupt .hdr: bad run length in scanline " + std::to_string(row));
                    }
                    cursor.skip(run ? 1 : size_t(count));
                    filled += count;
                }
            }
        }
    }
    if (cursor.overran()) {
        throw InputError("truncated .hdr: the pixel data ends early");
    }
    return size;
}

RadianceImageSize readRadianceHeader(std::span<const uint8_t> bytes)
{
    ByteCursor cursor(bytes);
    return parseHeader(cursor);
}

} // namespace lumar
