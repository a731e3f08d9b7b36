// The setup view's overlay (gles_renderer/overlay, app/setup_overlay.h) drawn by the renderer
// after compositing: a tag's outline lies on its projected corners (within 1 px), text stays
// in its box, and a frame without the overlay — before it was ever drawn, or after — is what
// the renderer composited, bit for bit.
#include <cmath>

#include <glm/gtc/matrix_transform.hpp>
#include <gtest/gtest.h>

#include "gl/gl_test_support.h"
#include "gles_renderer/overlay/bitmap_font.h"
#include "setup_overlay.h"

namespace lumar {
namespace {

constexpr int kWidth = 320, kHeight = 240;
constexpr uint8_t kGrey = 100;

const uint8_t* pixel(const Image8& image, int x, int y)
{
    return &image.data[(size_t(y) * size_t(image.width) + size_t(x)) * 3];
}

bool is(const uint8_t* p, const OverlayColor& c)
{
    return p[0] == c.r && p[1] == c.g && p[2] == c.b;
}

// Distance from `p` to the segment a-b.
double distanceToSegment(glm::dvec2 p, glm::dvec2 a, glm::dvec2 b)
{
    const glm::dvec2 ab = b - a;
    const double t = glm::clamp(glm::dot(p - a, ab) / glm::dot(ab, ab), 0.0, 1.0);
    return glm::length(p - (a + t * ab));
}

double distanceToOutline(glm::dvec2 p, const std::array<glm::dvec2, 4>& corners)
{
    double best = 1e9;
    for (int i = 0; i < 4; ++i)
        best = std::min(best, distanceToSegment(p, corners[size_t(i)], corners[size_t((i + 1) % 4)]));
    return best;
}

// A tag of side 0.16 m seen at an angle, with its pose and its corners projected exactly.
TagDetection tiltedTag(const CameraIntrinsics& k)
{
    TagDetection d;
    d.id = 7;
    d.hasPose = true;
    d.reprojectionErrorPx = 0.25;
    const glm::dmat4 turn = glm::rotate(glm::rotate(glm::dmat4(1.0), 0.5, glm::dvec3(0, 1, 0)), 2.8,
                                        glm::dvec3(1, 0, 0)); // facing the camera, tilted
    d.cameraFromMarker.R = glm::dmat3(turn);
    d.cameraFromMarker.t = {0.03, -0.02, 0.6};
    const std::array<glm::dvec3, 4> corners = tagCornersInMarkerFrame(0.16);
    for (size_t i = 0; i < 4; ++i)
        d.corners[i] = k.project(d.cameraFromMarker.apply(corners[i]));
    return d;
}

TEST(OverlayTest, ATagOutlineLiesOnItsProjectedCornersWithinOnePixel)
{
    LUMAR_RENDERER_OR_SKIP(renderer, kWidth, kHeight);
    const CameraIntrinsics k = test::makeIntrinsics(kWidth, kHeight, 300, 300, 159.5, 119.5);
    const TagDetection tag = tiltedTag(k);
    SetupOverlayInput input;
    input.intrinsics = k;
    input.detections = std::span<const TagDetection>(&tag, 1);
    input.tagSize = [](int) { return 0.16; };
    OverlayScene overlay;
    buildSetupOverlay(input, overlay);
    ASSERT_EQ(overlay.lines.size(), 4u + 3u); // the outline and the three axes

    renderer.render(test::solidImage(kWidth, kHeight, kGrey, kGrey, kGrey), k, {});
    renderer.drawOverlay(overlay);
    Image8 frame;
    renderer.readback(frame);

    // Every outline pixel near the tag (the label below it shares the colour) lies on the
    // outline: within half the line's width plus a pixel of the projected edges.
    const float halfWidth = 0.5f * overlay.lines[0].widthPx;
    double minX = 1e9, maxX = -1e9, minY = 1e9, maxY = -1e9;
    for (const glm::dvec2& c : tag.corners) {
        minX = std::min(minX, c.x), maxX = std::max(maxX, c.x);
        minY = std::min(minY, c.y), maxY = std::max(maxY, c.y);
    }
    int outlinePixels = 0;
    for (int y = int(minY) - 3; y <= int(maxY) + 3; ++y)
        for (int x = int(minX) - 3; x <= int(maxX) + 3; ++x)
            if (is(pixel(frame, x, y), kOverlayTagWithPose)) {
                ++outlinePixels;
                EXPECT_LE(distanceToOutline({x, y}, tag.corners), halfWidth + 1.0) << "pixel " << x << "," << y;
            }
    EXPECT_GT(outlinePixels, 100);
    // Each projected corner has outline pixels within 1 px, and every point along each edge
    // (those not under an axis, drawn after the outline) has one within 1 px.
    const auto outlineNear = [&](glm::dvec2 p) {
        for (int dy = -1; dy <= 1; ++dy)
            for (int dx = -1; dx <= 1; ++dx) {
                const int x = int(std::lround(p.x)) + dx, y = int(std::lround(p.y)) + dy;
                if (glm::length(glm::dvec2(x, y) - p) <= 1.0 + 1e-9 && is(pixel(frame, x, y), kOverlayTagWithPose))
                    return true;
            }
        return false;
    };
    for (const glm::dvec2& c : tag.corners)
        EXPECT_TRUE(outlineNear(c)) << "corner " << c.x << "," << c.y;
    int edgeSamples = 0, edgeHits = 0;
    for (size_t i = 0; i < 4; ++i) {
        const glm::dvec2 a = tag.corners[i], b = tag.corners[(i + 1) % 4];
        const int steps = int(glm::length(b - a));
        for (int s = 0; s <= steps; ++s) {
            ++edgeSamples;
            edgeHits += outlineNear(a + (b - a) * (double(s) / steps)) ? 1 : 0;
        }
    }
    // Only where an axis crosses the outline may the outline's colour be missing.
    EXPECT_GE(edgeHits, edgeSamples - 12) << edgeHits << " of " << edgeSamples;

    // The axes start at the projected origin, in their own colours.
    const glm::dvec2 origin = k.project(tag.cameraFromMarker.t);
    const glm::dvec2 xEnd = k.project(tag.cameraFromMarker.apply({0.08, 0, 0}));
    const glm::dvec2 mid = 0.5 * (origin + xEnd);
    bool red = false;
    for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx)
            red = red || is(pixel(frame, int(std::lround(mid.x)) + dx, int(std::lround(mid.y)) + dy), kOverlayAxisX);
    EXPECT_TRUE(red) << "the x axis at " << mid.x << "," << mid.y;
}

TEST(OverlayTest, TextStaysInsideItsBoxAndSaysSomething)
{
    LUMAR_RENDERER_OR_SKIP(renderer, kWidth, kHeight);
    const CameraIntrinsics k = test::makeIntrinsics(kWidth, kHeight, 300, 300, 159.5, 119.5);
    const Image8 black = test::solidImage(kWidth, kHeight, 0, 0, 0);
    const BitmapFont& font = overlayFont();
    ASSERT_GT(font.cellWidth, 3);
    ASSERT_GT(font.cellHeight, 6);

    const auto draw = [&](const std::string& text, int scale) {
        OverlayScene overlay;
        overlay.texts.push_back({{20.0, 30.0}, text, {255, 255, 255, 255}, {0, 0, 0, 0}, scale, 0});
        renderer.render(black, k, {});
        renderer.drawOverlay(overlay);
        Image8 frame;
        renderer.readback(frame);
        return frame;
    };
    for (const int scale : {1, 2}) {
        const Image8 frame = draw("lumar 0123", scale);
        const int x0 = 20, y0 = 30, x1 = x0 + font.textWidth("lumar 0123", scale), y1 = y0 + font.cellHeight * scale;
        int lit = 0;
        for (int y = 0; y < kHeight; ++y)
            for (int x = 0; x < kWidth; ++x)
                if (pixel(frame, x, y)[0] != 0) {
                    ++lit;
                    EXPECT_TRUE(x >= x0 && x < x1 && y >= y0 && y < y1) << "scale " << scale << ": " << x << "," << y;
                }
        EXPECT_GT(lit, 40 * scale * scale);
        // The space between "lumar" and "0123" is a whole empty cell.
        const int spaceX = x0 + 5 * font.cellWidth * scale;
        for (int y = y0; y < y1; ++y)
            for (int x = spaceX; x < spaceX + font.cellWidth * scale; ++x)
                EXPECT_EQ(pixel(frame, x, y)[0], 0) << x << "," << y;
    }
    // Different characters, different pixels.
    EXPECT_NE(draw("0", 1).data, draw("8", 1).data);
}

TEST(OverlayTest, FramesWithoutTheOverlayAreBitIdenticalBeforeAndAfterIt)
{
    LUMAR_RENDERER_OR_SKIP(renderer, kWidth, kHeight);
    const CameraIntrinsics k = test::makeIntrinsics(kWidth, kHeight, 300, 300, 159.5, 119.5);
    renderer.setEnvironment(test::uniformEnvironment(0.8f), 1.0f);
    GltfMaterial material;
    material.baseColorFactor = glm::vec4(0.8f, 0.3f, 0.2f, 1.0f);
    const ModelId quad = renderer.addModel(test::cameraFacingRectangle(-0.1f, -0.08f, 0.1f, 0.08f, material));
    Image8 background = test::solidImage(kWidth, kHeight, 0, 0, 0);
    for (size_t i = 0; i < background.data.size(); ++i)
        background.data[i] = uint8_t(i * 13 % 251);
    const DrawItem item{quad, test::translation(0.02, 0.01, 0.5)};
    const std::span<const DrawItem> items(&item, 1);

    // A second renderer that never draws an overlay: the reference.
    LUMAR_RENDERER_OR_SKIP(reference, kWidth, kHeight);
    reference.setEnvironment(test::uniformEnvironment(0.8f), 1.0f);
    const ModelId referenceQuad = reference.addModel(test::cameraFacingRectangle(-0.1f, -0.08f, 0.1f, 0.08f, material));
    ASSERT_EQ(referenceQuad, quad);
    reference.render(background, k, items);
    Image8 expected;
    reference.readback(expected);

    Image8 before, with, empty, after;
    renderer.render(background, k, items);
    renderer.readback(before);
    renderer.render(background, k, items);
    renderer.drawOverlay(OverlayScene{}); // nothing to draw: nothing drawn
    renderer.readback(empty);
    OverlayScene overlay;
    overlay.lines.push_back({{10, 10}, {300, 200}, {255, 0, 0, 255}, 3.0f});
    overlay.texts.push_back({{5, 5}, "status", {255, 255, 255, 255}, {0, 0, 0, 170}, 1, 2});
    renderer.render(background, k, items);
    renderer.drawOverlay(overlay);
    renderer.readback(with);
    renderer.render(background, k, items);
    renderer.readback(after);

    EXPECT_EQ(before.data, expected.data);
    EXPECT_EQ(empty.data, expected.data);
    EXPECT_NE(with.data, expected.data);
    EXPECT_EQ(after.data, expected.data) << "the overlay left a trace in GL's state";
}

TEST(OverlayTest, NothingBehindTheCameraIsDrawn)
{
    const CameraIntrinsics k = test::makeIntrinsics(kWidth, kHeight, 300, 300, 159.5, 119.5);
    TagDetection behind = tiltedTag(k);
    behind.cameraFromMarker.t.z = -0.6;
    MapDetection map;
    map.index = 0;
    map.name = "board";
    map.cameraFromMap.t = {0, 0, -1};
    SetupOverlayInput input;
    input.intrinsics = k;
    input.detections = std::span<const TagDetection>(&behind, 1);
    input.maps = std::span<const MapDetection>(&map, 1);
    input.tagSize = [](int) { return 0.16; };
    input.mapAxisLength = [](int) { return 0.2; };
    OverlayScene overlay;
    buildSetupOverlay(input, overlay);
    EXPECT_EQ(overlay.lines.size(), 4u); // the detected outline alone: no axes, no map
    ASSERT_EQ(overlay.texts.size(), 1u);
    EXPECT_NE(overlay.texts[0].text.find("id 7"), std::string::npos);
}

// The tracker's search windows (TagTracker::searchedWindows) drawn thin in their own colour:
// every pixel the overlay changed lies on a window's border (within 1 px plus half the line's
// width of the border pixels' centres), and every border pixel was drawn.
TEST(OverlayTest, SearchWindowsAreOutlinedOnTheirBorderPixels)
{
    LUMAR_RENDERER_OR_SKIP(renderer, kWidth, kHeight);
    const CameraIntrinsics k = test::makeIntrinsics(kWidth, kHeight, 300, 300, 159.5, 119.5);
    const SearchWindow windows[] = {{16, 24, 120, 104}, {200, 136, 320, 240}}; // the second at the image's corner
    SetupOverlayInput input;
    input.intrinsics = k;
    input.searchWindows = windows;
    OverlayScene overlay;
    buildSetupOverlay(input, overlay);
    ASSERT_EQ(overlay.lines.size(), 8u);
    for (const OverlayLine& line : overlay.lines) {
        EXPECT_EQ(line.color, kOverlaySearchWindow);
        EXPECT_LT(line.widthPx, 2.0f); // thinner than the tags' outlines
    }
    EXPECT_FALSE(kOverlaySearchWindow == kOverlayTagWithPose || kOverlaySearchWindow == kOverlayTagWithoutPose);

    renderer.render(test::solidImage(kWidth, kHeight, kGrey, kGrey, kGrey), k, {});
    renderer.drawOverlay(overlay);
    Image8 frame;
    renderer.readback(frame);

    const auto border = [](const SearchWindow& w) {
        return std::array<glm::dvec2, 4>{glm::dvec2(w.x0, w.y0), glm::dvec2(w.x1 - 1, w.y0),
                                         glm::dvec2(w.x1 - 1, w.y1 - 1), glm::dvec2(w.x0, w.y1 - 1)};
    };
    const auto changed = [&](int x, int y) {
        const uint8_t* p = pixel(frame, x, y);
        return p[0] != kGrey || p[1] != kGrey || p[2] != kGrey;
    };
    const double tolerance = 0.5 * overlay.lines[0].widthPx + 1.0;
    int drawn = 0;
    for (int y = 0; y < kHeight; ++y)
        for (int x = 0; x < kWidth; ++x)
            if (changed(x, y)) {
                ++drawn;
                const uint8_t* p = pixel(frame, x, y);
                EXPECT_TRUE(p[2] > p[0] + 100 && p[1] > p[0] + 100) << "not cyan at " << x << "," << y;
                double nearest = 1e9;
                for (const SearchWindow& w : windows)
                    nearest = std::min(nearest, distanceToOutline({x, y}, border(w)));
                EXPECT_LE(nearest, tolerance) << "pixel " << x << "," << y;
            }
    int perimeter = 0;
    for (const SearchWindow& w : windows) {
        for (int x = w.x0; x < w.x1; ++x) {
            EXPECT_TRUE(changed(x, w.y0)) << x << "," << w.y0;
            EXPECT_TRUE(changed(x, w.y1 - 1)) << x << "," << w.y1 - 1;
        }
        for (int y = w.y0; y < w.y1; ++y) {
            EXPECT_TRUE(changed(w.x0, y)) << w.x0 << "," << y;
            EXPECT_TRUE(changed(w.x1 - 1, y)) << w.x1 - 1 << "," << y;
        }
        perimeter += 2 * (w.x1 - w.x0) + 2 * (w.y1 - w.y0) - 4;
    }
    EXPECT_EQ(drawn, perimeter); // a 1-px line: the border pixels, nothing else
}

} // namespace
} // namespace lumar
