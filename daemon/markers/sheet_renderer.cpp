#include "markers/sheet_renderer.h"

#include <cctype>
#include <cmath>
#include <map>
#include <memory>
#include <string>

#include <cairo-pdf.h>
#include <cairo-svg.h>
#include <cairo.h>

#include "core/error.h"

namespace lumar {
namespace {

constexpr double kMmPerInch = 25.4;
constexpr double kPointsPerMm = 72.0 / kMmPerInch;

using SurfacePtr = std::unique_ptr<cairo_surface_t, decltype(&cairo_surface_destroy)>;
using ContextPtr = std::unique_ptr<cairo_t, decltype(&cairo_destroy)>;

void check(cairo_status_t status, const std::filesystem::path& file)
{
    if (status != CAIRO_STATUS_SUCCESS)
        throw RuntimeError(file.string() + ": cannot write: " + cairo_status_to_string(status));
}

// All black cells of a tag as one path and one fill: cells drawn one by one would leave
// antialiasing seams between neighbours in the PNG and in a PDF viewer.
void drawTag(cairo_t* cr, const PlacedTag& placed, const TagPattern& pattern)
{
    for (int row = 0; row < pattern.cells; ++row)
        for (int column = 0; column < pattern.cells; ++column)
            if (pattern.isBlack(row, column))
                cairo_rectangle(cr, placed.leftMm + column * placed.cellMm, placed.topMm + row * placed.cellMm,
                                placed.cellMm, placed.cellMm);
    cairo_set_source_rgb(cr, 0, 0, 0);
    cairo_fill(cr);
}

// Centimetres alternately black and white inside a thin frame, with a tick at each end.
void drawScaleBar(cairo_t* cr, const ScaleBar& bar)
{
    cairo_set_source_rgb(cr, 0, 0, 0);
    for (int cm = 0; cm < int(bar.lengthMm / 10.0); cm += 2)
        cairo_rectangle(cr, bar.leftMm + cm * 10.0, bar.topMm, 10.0, bar.heightMm);
    cairo_fill(cr);
    const double line = 0.2;
    cairo_set_line_width(cr, line);
    cairo_rectangle(cr, bar.leftMm + line / 2, bar.topMm + line / 2, bar.lengthMm - line, bar.heightMm - line);
    cairo_move_to(cr, bar.leftMm + line / 2, bar.topMm - 1.5);
    cairo_line_to(cr, bar.leftMm + line / 2, bar.topMm);
    cairo_move_to(cr, bar.leftMm + bar.lengthMm - line / 2, bar.topMm - 1.5);
    cairo_line_to(cr, bar.leftMm + bar.lengthMm - line / 2, bar.topMm);
    cairo_stroke(cr);
}

void drawPage(cairo_t* cr, const SheetPage& page, const TagFamilyPatterns& family, std::map<int, TagPattern>& patterns)
{
    cairo_set_source_rgb(cr, 1, 1, 1);
    cairo_paint(cr);
    for (const PlacedTag& tag : page.tags) {
        auto it = patterns.find(tag.id);
        if (it == patterns.end())
            it = patterns.emplace(tag.id, family.pattern(tag.id)).first;
        drawTag(cr, tag, it->second);
    }
    drawScaleBar(cr, page.scaleBar);
    cairo_select_font_face(cr, "DejaVu Sans", CAIRO_FONT_SLANT_NORMAL, CAIRO_FONT_WEIGHT_NORMAL);
    cairo_set_source_rgb(cr, 0, 0, 0);
    for (const PlacedText& text : page.texts) {
        cairo_set_font_size(cr, text.heightMm);
        cairo_move_to(cr, text.xMm, text.baselineMm);
        cairo_show_text(cr, text.text.c_str());
    }
}

std::filesystem::path pageFile(const std::filesystem::path& out, size_t page, size_t pages)
{
    if (pages == 1)
        return out;
    std::filesystem::path file = out;
    file.replace_filename(out.stem().string() + "-" + std::to_string(page + 1) + out.extension().string());
    return file;
}

} // namespace

std::vector<std::filesystem::path> writeMarkerSheet(const MarkerSheet& sheet, const TagFamilyPatterns& family,
                                                    const std::filesystem::path& out, int dpi)
{
    std::string extension = out.extension().string();
    for (char& c : extension)
        c = char(std::tolower(static_cast<unsigned char>(c)));
    std::map<int, TagPattern> patterns;
    const double widthMm = sheet.paper.widthMm, heightMm = sheet.paper.heightMm;

    if (extension == ".pdf") {
        SurfacePtr surface(cairo_pdf_surface_create(out.c_str(), widthMm * kPointsPerMm, heightMm * kPointsPerMm),
                           cairo_surface_destroy);
        check(cairo_surface_status(surface.get()), out);
        ContextPtr cr(cairo_create(surface.get()), cairo_destroy);
        cairo_scale(cr.get(), kPointsPerMm, kPointsPerMm);
        for (const SheetPage& page : sheet.pages) {
            drawPage(cr.get(), page, family, patterns);
            cairo_show_page(cr.get());
        }
        check(cairo_status(cr.get()), out);
        cairo_surface_finish(surface.get());
        check(cairo_surface_status(surface.get()), out);
        return {out};
    }

    std::vector<std::filesystem::path> files;
    for (size_t i = 0; i < sheet.pages.size(); ++i) {
        const std::filesystem::path file = pageFile(out, i, sheet.pages.size());
        if (extension == ".svg") {
            // Millimetres as the document unit: width="210mm", and user space in mm.
            SurfacePtr surface(cairo_svg_surface_create(file.c_str(), widthMm, heightMm), cairo_surface_destroy);
            check(cairo_surface_status(surface.get()), file);
            cairo_svg_surface_set_document_unit(surface.get(), CAIRO_SVG_UNIT_MM);
            ContextPtr cr(cairo_create(surface.get()), cairo_destroy);
            drawPage(cr.get(), sheet.pages[i], family, patterns);
            check(cairo_status(cr.get()), file);
            cairo_surface_finish(surface.get());
            check(cairo_surface_status(surface.get()), file);
        } else if (extension == ".png") {
            const double pixelsPerMm = dpi / kMmPerInch;
            SurfacePtr surface(cairo_image_surface_create(CAIRO_FORMAT_RGB24, int(std::ceil(widthMm * pixelsPerMm)),
                                                          int(std::ceil(heightMm * pixelsPerMm))),
                               cairo_surface_destroy);
            check(cairo_surface_status(surface.get()), file);
            ContextPtr cr(cairo_create(surface.get()), cairo_destroy);
            cairo_scale(cr.get(), pixelsPerMm, pixelsPerMm);
            drawPage(cr.get(), sheet.pages[i], family, patterns);
            check(cairo_status(cr.get()), file);
            check(cairo_surface_write_to_png(surface.get(), file.c_str()), file);
        } else {
            throw InputError("--out " + out.string() + ": write .pdf, .png or .svg");
        }
        files.push_back(file);
    }
    return files;
}

} // namespace lumar
