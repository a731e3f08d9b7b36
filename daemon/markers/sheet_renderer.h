// Draws a marker sheet (markers/marker_sheet.h) with Debian's cairo: PDF and SVG as vector
// pages at exact physical size, PNG at a given resolution. cairo rather than a writer of our
// own: PDF needs fonts embedded and page streams compressed, SVG and PNG come with it, and
// the same drawing code serves all three.
#pragma once

#include <filesystem>
#include <vector>

#include "markers/marker_sheet.h"

namespace lumar {

// Writes `sheet` to `out`, by its extension: .pdf (one document, all pages), .svg or .png
// (one file a page: `out` itself when there is one page, else NAME-1.png, NAME-2.png, ...;
// PNG at `dpi` pixels per inch). Returns the files written. Throws InputError for another
// extension and RuntimeError when a file cannot be written.
std::vector<std::filesystem::path> writeMarkerSheet(const MarkerSheet& sheet, const TagFamilyPatterns& family,
                                                    const std::filesystem::path& out, int dpi);

} // namespace lumar
