// The overlay's font: printable ASCII of DejaVu Sans Mono rasterised by FreeType at build time
// (font/bitmap_font_gen.cpp) into one row of equal cells of 8-bit coverage.
#pragma once

#include <span>
#include <string_view>

namespace lumar {

struct BitmapFont {
    int cellWidth = 0;                    // pixels: every glyph's advance (the font is monospaced)
    int cellHeight = 0;                   // pixels: ascender to descender
    int ascender = 0;                     // pixels from a cell's top to the baseline
    int first = 0;                        // the character in cell 0
    int count = 0;                        // cells, left to right
    std::span<const unsigned char> atlas; // count * cellWidth wide, cellHeight high, row 0 at the top

    [[nodiscard]] int atlasWidth() const { return count * cellWidth; }
    // The cell of `c`, or that of '?' for a character the font lacks.
    [[nodiscard]] int cellOf(char c) const
    {
        const int code = static_cast<unsigned char>(c);
        return code >= first && code < first + count ? code - first : '?' - first;
    }
    // Width in pixels of `text` on one line at `scale`.
    [[nodiscard]] int textWidth(std::string_view text, int scale = 1) const
    {
        return int(text.size()) * cellWidth * scale;
    }
};

// The font built into lumar (generated source).
const BitmapFont& overlayFont();

} // namespace lumar
