// lumar markers as a user runs it: the printed page, rendered back to pixels (pdftoppm for
// the PDF, the PNG as written), holds every requested tag, found by lumar's own detector,
// with its side at the requested size at the stated resolution; a board's map file passes
// `lumar check-config` and describes the layout that was printed; bad input is one line and
// exit 2.
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <map>

#include <gtest/gtest.h>

#include "config/config.h"
#include "core/camera_model.h"
#include "integration/run_lumar.h"
#include "output/frame_writer.h"
#include "tracking/tag_tracker.h"

namespace lumar {
namespace {

namespace fs = std::filesystem;
using test::runLumar;

constexpr double kMetresPerInch = 0.0254;

std::map<int, TagDetection> detectTags(const fs::path& image, const std::string& family)
{
    const Image8 luma = readImage(image, 1);
    TrackingConfig tracking;
    tracking.family = family;
    tracking.quadDecimate = 2.0; // the tags are hundreds of pixels wide; refine_edges restores accuracy
    TagTracker tracker(tracking, defaultIntrinsics(luma.width, luma.height), TagSizes{});
    std::map<int, TagDetection> byId;
    for (const TagDetection& d : tracker.detect(luma))
        byId[d.id] = d;
    return byId;
}

double meanSidePx(const TagDetection& d)
{
    double sum = 0.0;
    for (int i = 0; i < 4; ++i)
        sum += glm::length(d.corners[size_t(i)] - d.corners[size_t((i + 1) % 4)]);
    return sum / 4.0;
}

glm::dvec2 centrePx(const TagDetection& d)
{
    return (d.corners[0] + d.corners[1] + d.corners[2] + d.corners[3]) / 4.0;
}

// Renders page 1 of `pdf` at `dpi` into a grey PNG with Poppler.
fs::path renderPdf(const fs::path& pdf, int dpi)
{
    const fs::path stem = pdf.parent_path() / "page";
    const std::string command = "pdftoppm -gray -png -singlefile -r " + std::to_string(dpi) + " " +
                                test::shellQuote(pdf) + " " + test::shellQuote(stem.string());
    if (std::system(command.c_str()) != 0)
        return {};
    return stem.string() + ".png";
}

bool havePdftoppm()
{
    return std::system("command -v pdftoppm >/dev/null 2>&1") == 0;
}

void expectTagsAtSize(const std::map<int, TagDetection>& found, const std::vector<int>& ids, double size, int dpi)
{
    const double expected = size / kMetresPerInch * dpi;
    for (int id : ids) {
        const auto it = found.find(id);
        ASSERT_NE(it, found.end()) << "id " << id << " not found";
        EXPECT_NEAR(meanSidePx(it->second), expected, 0.005 * expected) << "id " << id;
    }
}

TEST(Markers, PdfPageHoldsEveryTagAtItsSize)
{
    if (!havePdftoppm())
        GTEST_SKIP() << "pdftoppm (poppler-utils) is not installed";
    const fs::path dir = test::scratchDirectory("markers-pdf");
    const auto r = runLumar({"markers", "--ids", "0-3", "--size", "0.05", "--out", (dir / "tags.pdf").string()}, dir);
    ASSERT_EQ(r.exitCode, 0) << r.err;
    const int dpi = 200;
    const fs::path page = renderPdf(dir / "tags.pdf", dpi);
    ASSERT_FALSE(page.empty()) << "pdftoppm failed";
    const auto found = detectTags(page, "tag36h11");
    EXPECT_EQ(found.size(), 4u);
    expectTagsAtSize(found, {0, 1, 2, 3}, 0.05, dpi);
}

TEST(Markers, PngAtTheStatedDpiForAnotherFamily)
{
    const fs::path dir = test::scratchDirectory("markers-png");
    const auto r = runLumar({"markers", "--family", "tag25h9", "--ids", "3,7", "--size", "0.06", "--page", "letter",
                             "--dpi", "150", "--out", (dir / "tags.png").string()},
                            dir);
    ASSERT_EQ(r.exitCode, 0) << r.err;
    const Image8 page = readImage(dir / "tags.png", 1);
    EXPECT_EQ(page.width, int(std::ceil(215.9 / 25.4 * 150))); // Letter at 150 dpi
    const auto found = detectTags(dir / "tags.png", "tag25h9");
    EXPECT_EQ(found.size(), 2u);
    expectTagsAtSize(found, {3, 7}, 0.06, 150);
}

TEST(Markers, SvgIsInMillimetres)
{
    const fs::path dir = test::scratchDirectory("markers-svg");
    const auto r = runLumar({"markers", "--ids", "5", "--size", "0.1", "--out", (dir / "tag.svg").string()}, dir);
    ASSERT_EQ(r.exitCode, 0) << r.err;
    const std::string svg = test::readText(dir / "tag.svg");
    EXPECT_NE(svg.find("width=\"210mm\""), std::string::npos) << svg.substr(0, 400);
    EXPECT_NE(svg.find("height=\"297mm\""), std::string::npos);
}

TEST(Markers, ManyTagsFillSeveralPages)
{
    const fs::path dir = test::scratchDirectory("markers-pages");
    const auto r =
        runLumar({"markers", "--ids", "0-5", "--size", "0.06", "--dpi", "50", "--out", (dir / "t.png").string()}, dir);
    ASSERT_EQ(r.exitCode, 0) << r.err;
    // 0.06 m tags take 75 mm with their white ring, 86 mm with their labels: four to an A4
    // page (190 x 251 mm inside the margins, header and scale bar).
    EXPECT_TRUE(fs::exists(dir / "t-1.png"));
    EXPECT_TRUE(fs::exists(dir / "t-2.png"));
    EXPECT_FALSE(fs::exists(dir / "t-3.png"));
    EXPECT_FALSE(fs::exists(dir / "t.png"));
}

TEST(Markers, BoardMapMatchesThePrintedLayout)
{
    if (!havePdftoppm())
        GTEST_SKIP() << "pdftoppm (poppler-utils) is not installed";
    const fs::path dir = test::scratchDirectory("markers-board");
    const auto r = runLumar({"markers", "--board", "2x3", "--ids", "10-15", "--size", "0.04", "--spacing", "0.015",
                             "--map-name", "desk", "--out", (dir / "board.pdf").string()},
                            dir);
    ASSERT_EQ(r.exitCode, 0) << r.err;
    const fs::path mapFile = dir / "board.toml";
    const auto check = runLumar({"check-config", mapFile.string()}, dir);
    ASSERT_EQ(check.exitCode, 0) << check.err << test::readText(mapFile);

    const Config config = loadConfig(mapFile);
    ASSERT_EQ(config.maps.size(), 1u);
    EXPECT_EQ(config.maps[0].name, "desk");
    ASSERT_EQ(config.maps[0].tags.size(), 6u);

    const int dpi = 150;
    const fs::path page = renderPdf(dir / "board.pdf", dpi);
    ASSERT_FALSE(page.empty());
    const auto found = detectTags(page, config.tracking.family);
    expectTagsAtSize(found, {10, 11, 12, 13, 14, 15}, 0.04, dpi);
    if (found.size() != 6u)
        return;
    // Every tag's centre relative to the first, measured on the page (pixels to metres, y up)
    // against the map file's positions.
    const double metresPerPx = kMetresPerInch / dpi;
    const glm::dvec2 origin = centrePx(found.at(config.maps[0].tags[0].id));
    for (const MapTagConfig& tag : config.maps[0].tags) {
        EXPECT_DOUBLE_EQ(tag.size, 0.04);
        EXPECT_EQ(tag.rotationDeg, glm::dvec3(0.0));
        const glm::dvec2 offsetPx = centrePx(found.at(tag.id)) - origin;
        const glm::dvec2 measured{offsetPx.x * metresPerPx, -offsetPx.y * metresPerPx};
        const glm::dvec2 mapped = glm::dvec2(tag.position - config.maps[0].tags[0].position);
        EXPECT_NEAR(measured.x, mapped.x, 0.0005) << "id " << tag.id;
        EXPECT_NEAR(measured.y, mapped.y, 0.0005) << "id " << tag.id;
        EXPECT_EQ(tag.position.z, 0.0);
    }
    // The board's centre is the map's origin.
    glm::dvec3 sum(0.0);
    for (const MapTagConfig& tag : config.maps[0].tags)
        sum += tag.position;
    EXPECT_NEAR(glm::length(sum), 0.0, 1e-9);
}

void expectBadInput(const std::vector<std::string>& args, const std::string& mention)
{
    const fs::path dir = test::scratchDirectory("markers-bad");
    std::vector<std::string> all{"markers"};
    all.insert(all.end(), args.begin(), args.end());
    const auto r = runLumar(all, dir);
    EXPECT_EQ(r.exitCode, 2) << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
    EXPECT_NE(r.err.find(mention), std::string::npos) << r.err;
    EXPECT_TRUE(r.out.empty()) << r.out;
}

TEST(Markers, BadInputIsOneLineAndExitTwo)
{
    const std::string out = (fs::temp_directory_path() / "lumar-markers-bad.pdf").string();
    expectBadInput({"--ids", "585-587", "--size", "0.1", "--out", out}, "ids 0-586");
    expectBadInput({"--family", "tag16h5", "--ids", "30", "--size", "0.1", "--out", out}, "ids 0-29");
    expectBadInput({"--ids", "0-x", "--size", "0.1", "--out", out}, "--ids");
    expectBadInput({"--ids", "0", "--size", "0.2", "--out", out}, "A4 page");
    expectBadInput({"--ids", "0", "--size", "0.18", "--page", "letter", "--out", out}, "Letter page");
    expectBadInput({"--ids", "0", "--size", "0", "--out", out}, "--size");
    expectBadInput({"--ids", "0", "--size", "-0.1", "--out", out}, "--size");
    expectBadInput({"--ids", "0", "--size", "abc", "--out", out}, "--size");
    expectBadInput({"--ids", "0", "--size", "0.1", "--out", "tag.jpg"}, ".pdf, .png or .svg");
    expectBadInput({"--ids", "0", "--size", "0.1", "--page", "a3", "--out", out}, "a3");
    expectBadInput({"--ids", "0", "--size", "0.1", "--family", "tag99", "--out", out}, "tag99");
    expectBadInput({"--board", "2x2", "--ids", "0-2", "--size", "0.05", "--out", out}, "4 ids");
    expectBadInput({"--board", "2x2", "--ids", "0-3", "--size", "0.05", "--spacing", "0.005", "--out", out},
                   "--spacing");
    expectBadInput({"--board", "2by2", "--ids", "0-3", "--size", "0.05", "--out", out}, "ROWSxCOLS");
    expectBadInput({"--board", "4x4", "--ids", "0-15", "--size", "0.05", "--out", out}, "A4 page");
    expectBadInput({"--ids", "0", "--size", "0.05", "--spacing", "0.02", "--out", out}, "--board");
    EXPECT_FALSE(fs::exists(out));
}

} // namespace
} // namespace lumar
