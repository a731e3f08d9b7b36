#include "markers/marker_sheet.h"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <set>

#include "core/error.h"

namespace lumar {
namespace {

// Page furniture, millimetres. Most printers cannot print the outer 5 mm of a sheet.
constexpr double kMarginMm = 10.0;
constexpr double kFontMm = 3.5; // about 10 pt
constexpr double kLineMm = 5.0;
constexpr double kHeaderMm = 10.0; // the header line and the space under it
constexpr double kFooterMm = 16.0; // the scale bar and its caption
constexpr double kGapMm = 8.0;     // between the items of a page of single tags
// Text width estimate for layout only: DejaVu Sans averages about 0.55 em per character.
constexpr double kCharWidthEm = 0.6;

double textWidthMm(const std::string& text, double fontMm)
{
    return double(text.size()) * kCharWidthEm * fontMm;
}

std::string formatNumber(double v, const char* format = "%.6g")
{
    char out[40];
    std::snprintf(out, sizeof out, format, v + 0.0); // + 0.0: no "-0"
    return out;
}

std::string millimetres(double metres)
{
    return formatNumber(metres * 1000.0, "%.4g") + " mm";
}

// A TOML float: always with a decimal point or an exponent.
std::string tomlFloat(double v)
{
    std::string text = formatNumber(std::fabs(v) < 1e-12 ? 0.0 : v, "%.9g");
    if (text.find_first_of(".e") == std::string::npos)
        text += ".0";
    return text;
}

// "0-3,7": consecutive runs as ranges.
std::string idRuns(const std::vector<int>& ids)
{
    std::string text;
    for (size_t i = 0; i < ids.size();) {
        size_t j = i;
        while (j + 1 < ids.size() && ids[j + 1] == ids[j] + 1)
            ++j;
        text += (text.empty() ? "" : ",") + std::to_string(ids[i]);
        if (j > i)
            text += "-" + std::to_string(ids[j]);
        i = j + 1;
    }
    return text;
}

std::optional<int> parseId(const std::string& text)
{
    if (text.empty() || !std::all_of(text.begin(), text.end(), [](unsigned char c) { return std::isdigit(c); }) ||
        text.size() > 9)
        return std::nullopt;
    return std::atoi(text.c_str());
}

double cellOf(double size, const TagFamilyPatterns& family)
{
    return size / family.borderCells();
}

// The white ring around the measured square, in metres.
double quietOf(double size, const TagFamilyPatterns& family)
{
    return cellOf(size, family) * (family.printedCells() - family.borderCells()) / 2.0;
}

void checkFits(double widthMm, double heightMm, double availableWidthMm, double availableHeightMm,
               const std::string& what, const Paper& paper)
{
    if (widthMm <= availableWidthMm && heightMm <= availableHeightMm)
        return;
    throw InputError("--size: " + what + " needs " + formatNumber(widthMm, "%.1f") + " x " +
                     formatNumber(heightMm, "%.1f") + " mm with its white border and label; a " + paper.name +
                     " page has " + formatNumber(availableWidthMm, "%.1f") + " x " +
                     formatNumber(availableHeightMm, "%.1f") + " mm for it");
}

SheetPage pageFrame(const Paper& paper, const std::string& header)
{
    SheetPage page;
    page.texts.push_back({header, kMarginMm, kMarginMm + kFontMm, kFontMm});
    page.scaleBar.leftMm = kMarginMm;
    page.scaleBar.topMm = paper.heightMm - kMarginMm - kFooterMm + 2.0;
    page.texts.push_back({"10 cm: if this bar is not 100 mm long, print at actual size (100 %)", kMarginMm,
                          page.scaleBar.topMm + page.scaleBar.heightMm + kLineMm, kFontMm});
    return page;
}

MarkerSheet layOutSingles(const MarkerRequest& request, const TagFamilyPatterns& family, const std::string& header)
{
    const double cellMm = cellOf(request.size, family) * 1000.0;
    const double sideMm = cellMm * family.printedCells();
    const double contentTop = kMarginMm + kHeaderMm;
    const double contentBottom = request.paper.heightMm - kMarginMm - kFooterMm;
    const double contentRight = request.paper.widthMm - kMarginMm;
    const std::string sizeLine = millimetres(request.size) + " border to border";

    MarkerSheet sheet{request.paper, {}};
    double x = kMarginMm, y = contentTop, rowHeight = 0.0;
    for (int id : request.ids) {
        const std::string idLine = family.name() + " id " + std::to_string(id);
        const double width = std::max({sideMm, textWidthMm(idLine, kFontMm), textWidthMm(sizeLine, kFontMm)});
        const double height = sideMm + 1.0 + 2.0 * kLineMm;
        checkFits(width, height, contentRight - kMarginMm, contentBottom - contentTop,
                  "a " + family.name() + " tag of " + millimetres(request.size), request.paper);
        if (x + width > contentRight) { // next row
            x = kMarginMm;
            y += rowHeight + kGapMm;
            rowHeight = 0.0;
        }
        if (sheet.pages.empty() || y + height > contentBottom) { // next page
            sheet.pages.push_back(pageFrame(request.paper, header));
            x = kMarginMm;
            y = contentTop;
            rowHeight = 0.0;
        }
        SheetPage& page = sheet.pages.back();
        page.tags.push_back({id, x, y, cellMm});
        page.texts.push_back({idLine, x, y + sideMm + 1.0 + kFontMm, kFontMm});
        page.texts.push_back({sizeLine, x, y + sideMm + 1.0 + kLineMm + kFontMm, kFontMm});
        x += width + kGapMm;
        rowHeight = std::max(rowHeight, height);
    }
    return sheet;
}

MarkerSheet layOutBoard(const MarkerRequest& request, const TagFamilyPatterns& family, const std::string& header)
{
    const BoardShape& board = *request.board;
    const double cellMm = cellOf(request.size, family) * 1000.0;
    const double quietMm = quietOf(request.size, family) * 1000.0;
    const double pitchMm = (request.size + board.spacing) * 1000.0;
    const double sizeMm = request.size * 1000.0;
    const double widthMm = board.columns * pitchMm - board.spacing * 1000.0 + 2.0 * quietMm;
    const double heightMm = board.rows * pitchMm - board.spacing * 1000.0 + 2.0 * quietMm;
    const std::vector<std::string> caption = {
        "map \"" + request.mapName + "\": " + family.name() + " ids " + idRuns(request.ids) + ", " +
            std::to_string(board.rows) + " x " + std::to_string(board.columns) + " row by row from the top left",
        "tags " + millimetres(request.size) + " border to border, " + millimetres(board.spacing) +
            " apart; map origin at the centre, x right, y up",
    };
    const double captionHeight = 1.0 + double(caption.size()) * kLineMm;
    const double availableWidth = request.paper.widthMm - 2.0 * kMarginMm;
    const double availableHeight = request.paper.heightMm - 2.0 * kMarginMm - kHeaderMm - kFooterMm;
    checkFits(widthMm, heightMm + captionHeight, availableWidth, availableHeight,
              "a " + std::to_string(board.rows) + "x" + std::to_string(board.columns) + " board of " +
                  millimetres(request.size) + " tags",
              request.paper);

    MarkerSheet sheet{request.paper, {pageFrame(request.paper, header)}};
    SheetPage& page = sheet.pages.back();
    const double left = kMarginMm + (availableWidth - widthMm) / 2.0;
    const double top = kMarginMm + kHeaderMm;
    // Each tag's id in the outer part of its own white ring, where it is far from the edge
    // the detector follows; left out when the ring is too narrow to hold legible text.
    const double idFontMm = std::min(0.4 * quietMm, 4.0);
    for (int row = 0; row < board.rows; ++row)
        for (int column = 0; column < board.columns; ++column) {
            const int id = request.ids[size_t(row * board.columns + column)];
            const double tagLeft = left + column * pitchMm, tagTop = top + row * pitchMm;
            page.tags.push_back({id, tagLeft, tagTop, cellMm});
            if (idFontMm >= 1.5)
                page.texts.push_back({"id " + std::to_string(id), tagLeft + quietMm,
                                      tagTop + 2.0 * quietMm + sizeMm - 0.2 * quietMm, idFontMm});
        }
    double baseline = top + heightMm + 1.0;
    for (const std::string& line : caption)
        page.texts.push_back({line, left, baseline += kLineMm, kFontMm});
    return sheet;
}

} // namespace

Paper paperNamed(const std::string& name)
{
    std::string lower = name;
    std::transform(lower.begin(), lower.end(), lower.begin(), [](unsigned char c) { return char(std::tolower(c)); });
    if (lower == "a4")
        return {"A4", 210.0, 297.0};
    if (lower == "letter")
        return {"Letter", 215.9, 279.4};
    throw InputError("--page: '" + name + "' is not a4 or letter");
}

std::vector<int> parseIdList(const std::string& text, const TagFamilyPatterns& family)
{
    std::vector<int> ids;
    std::set<int> seen;
    const auto bad = [&text](const std::string& why) { return InputError("--ids '" + text + "': " + why); };
    size_t start = 0;
    while (start <= text.size()) {
        const size_t comma = std::min(text.find(',', start), text.size());
        const std::string item = text.substr(start, comma - start);
        const size_t dash = item.find('-');
        const std::optional<int> first = parseId(item.substr(0, dash));
        const std::optional<int> last = dash == std::string::npos ? first : parseId(item.substr(dash + 1));
        if (!first || !last)
            throw bad("expected ids and ranges such as 0-3,7");
        if (*last < *first)
            throw bad("range " + item + " runs backwards");
        for (int id = *first; id <= *last; ++id) {
            if (id >= family.idCount())
                throw bad(family.name() + " has ids 0-" + std::to_string(family.idCount() - 1));
            if (!seen.insert(id).second)
                throw bad("id " + std::to_string(id) + " is listed twice");
            ids.push_back(id);
        }
        start = comma + 1;
    }
    return ids;
}

BoardShape parseBoardShape(const std::string& text)
{
    const size_t x = text.find_first_of("xX");
    const std::optional<int> rows = parseId(text.substr(0, x));
    const std::optional<int> columns = x == std::string::npos ? std::nullopt : parseId(text.substr(x + 1));
    if (!rows || !columns || *rows < 1 || *columns < 1 || *rows > 50 || *columns > 50)
        throw InputError("--board '" + text + "': expected ROWSxCOLS, 1..50 each (e.g. 2x3)");
    return {*rows, *columns, 0.0};
}

double minimumBoardSpacing(double size, const TagFamilyPatterns& family)
{
    return 2.0 * quietOf(size, family);
}

std::vector<BoardTag> boardLayout(const MarkerRequest& request)
{
    const BoardShape& board = *request.board;
    const double pitch = request.size + board.spacing;
    std::vector<BoardTag> tags;
    for (int row = 0; row < board.rows; ++row)
        for (int column = 0; column < board.columns; ++column)
            tags.push_back({request.ids[size_t(row * board.columns + column)],
                            (column - (board.columns - 1) / 2.0) * pitch, ((board.rows - 1) / 2.0 - row) * pitch});
    return tags;
}

MarkerSheet layOutMarkers(const MarkerRequest& request, const TagFamilyPatterns& family)
{
    if (!(request.size > 0.0) || !std::isfinite(request.size))
        throw InputError("--size: the tag side must be a positive number of metres");
    if (request.ids.empty())
        throw InputError("--ids: no ids given");
    const std::string header = "lumar markers: " + family.name() + " on " + request.paper.name +
                               ". Print at actual size (100 %), not 'fit to page'.";
    if (!request.board)
        return layOutSingles(request, family, header);
    const BoardShape& board = *request.board;
    if (int(request.ids.size()) != board.rows * board.columns)
        throw InputError("--ids: a " + std::to_string(board.rows) + "x" + std::to_string(board.columns) +
                         " board takes " + std::to_string(board.rows * board.columns) + " ids, " +
                         std::to_string(request.ids.size()) + " given");
    const double minimum = minimumBoardSpacing(request.size, family);
    if (!(board.spacing >= minimum * (1.0 - 1e-9)) || !std::isfinite(board.spacing))
        throw InputError("--spacing " + formatNumber(board.spacing) + ": " + millimetres(request.size) + " " +
                         family.name() + " tags need at least " + formatNumber(minimum) +
                         " m between their borders (their white rings)");
    for (char c : request.mapName)
        if (!std::isalnum(static_cast<unsigned char>(c)) && c != '_' && c != '-')
            throw InputError("--map-name '" + request.mapName + "': use letters, digits, '_' and '-'");
    if (request.mapName.empty())
        throw InputError("--map-name: the map needs a name");
    return layOutBoard(request, family, header);
}

std::string boardMapToml(const MarkerRequest& request, const TagFamilyPatterns& family)
{
    const BoardShape& board = *request.board;
    std::string text = "# The board `lumar markers` printed: " + std::to_string(board.rows) + "x" +
                       std::to_string(board.columns) + " " + family.name() + " tags of " + millimetres(request.size) +
                       ", " + millimetres(board.spacing) +
                       " apart.\n# Map frame: origin at the board's centre, x right, y up the page, z out of it.\n"
                       "# Objects stand on it with map = \"" +
                       request.mapName + "\".\n\n[tracking]\nfamily = \"" + family.name() +
                       "\"\n\n[[maps]]\nname = \"" + request.mapName + "\"\n";
    for (const BoardTag& tag : boardLayout(request))
        text += "\n[[maps.tags]]\nid = " + std::to_string(tag.id) + "\nsize = " + tomlFloat(request.size) +
                "\nposition = [" + tomlFloat(tag.x) + ", " + tomlFloat(tag.y) + ", 0.0]\n";
    return text;
}

} // namespace lumar
