// Structural check of a Radiance .hdr (RGBE) stream before stb_image decodes it.
//
// Debian's stb_image (2.27) trusts the stream: on a truncated file it reads zeros past the
// end, and a zero run length in an RLE scanline makes it loop forever. This walks the stream
// exactly the way stbi__hdr_load does, without decoding values, so a file that passes is
// one stb reads entirely from real bytes.
#pragma once

#include <cstdint>
#include <span>

namespace lumar {

struct RadianceImageSize {
    int width = 0;
    int height = 0;
};

// Throws InputError (a message without a file name; the caller adds it) when the header is
// not one stb_image accepts (-Y H +X W, 32-bit_rle_rgbe), a size is not positive, a scanline
// is malformed or the data ends before the last pixel.
RadianceImageSize checkRadianceStream(std::span<const uint8_t> bytes);

// The header's size alone (the same checks on the header, none on the pixels): for limits
// that refuse a file before its pixel stream is walked.
RadianceImageSize readRadianceHeader(std::span<const uint8_t> bytes);

} // namespace lumar
