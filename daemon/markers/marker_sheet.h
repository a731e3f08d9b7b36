// What `lumar markers` prints, laid out on paper: tags at their exact physical size, each
// with its id, family and size beside it (or a board of tags with a known layout, the
// [[maps]] entry it is), a 10 cm scale bar to check the printer's scaling, and pages as
// many as needed. Pure geometry in millimetres (origin at the page's top-left corner, y
// down, as on paper); markers/sheet_renderer.h draws it.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "markers/tag_pattern.h"

namespace lumar {

struct Paper {
    std::string name;
    double widthMm = 0.0, heightMm = 0.0;
};

// "a4" or "letter" (any case); throws InputError for another name.
Paper paperNamed(const std::string& name);

// "0-3", "5", "0,2,7-9": ids in the order given, each once. Throws InputError for a
// malformed list, a repeated id or an id outside [0, idCount).
std::vector<int> parseIdList(const std::string& text, const TagFamilyPatterns& family);

struct BoardShape {
    int rows = 0, columns = 0;
    double spacing = 0.0; // metres between neighbouring tags' borders (edge to edge)
};

// "2x3" (rows x columns, 1..50 each); throws InputError otherwise.
BoardShape parseBoardShape(const std::string& text);

struct MarkerRequest {
    std::vector<int> ids;
    double size = 0.0; // metres, the side the detector measures (TagFamilyPatterns::borderCells)
    Paper paper;
    std::optional<BoardShape> board; // ids fill it row by row from the top left
    std::string mapName = "board";
};

// A tag of a board in the map frame: origin at the board's centre, x right, y up the page,
// z out of it; every tag's frame is turned as the map's (rotation zero).
struct BoardTag {
    int id = 0;
    double x = 0.0, y = 0.0; // metres, the tag's centre
};

// The tags' centres of `request.board`; `request.board` must be set.
std::vector<BoardTag> boardLayout(const MarkerRequest& request);

// The smallest board spacing: the tags' white borders side by side.
double minimumBoardSpacing(double size, const TagFamilyPatterns& family);

struct PlacedTag {
    int id = 0;
    double leftMm = 0.0, topMm = 0.0; // the printed square's corner (quiet zone included)
    double cellMm = 0.0;
};

struct PlacedText {
    std::string text;
    double xMm = 0.0, baselineMm = 0.0; // the text's left end on its baseline
    double heightMm = 0.0;              // the font size
};

struct ScaleBar {
    double leftMm = 0.0, topMm = 0.0;
    double lengthMm = 100.0;
    double heightMm = 4.0;
};

struct SheetPage {
    std::vector<PlacedTag> tags;
    std::vector<PlacedText> texts;
    ScaleBar scaleBar;
};

struct MarkerSheet {
    Paper paper;
    std::vector<SheetPage> pages;
};

// Lays the request out. Throws InputError (naming the option at fault) for a size that is
// not positive or a page too small for one tag or the board, for a board whose id count
// differs from rows x columns, or a spacing below minimumBoardSpacing.
MarkerSheet layOutMarkers(const MarkerRequest& request, const TagFamilyPatterns& family);

// The [[maps]] entry of `request.board` as a configuration file of its own ([tracking]
// family and the map), for `lumar check-config` and to paste into a configuration.
std::string boardMapToml(const MarkerRequest& request, const TagFamilyPatterns& family);

} // namespace lumar
