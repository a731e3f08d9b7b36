// What the overlay pass draws over a finished frame: lines and labelled text in the frame's
// pixels, nothing more. The renderer knows no markers, maps or status: the application turns
// what it tracks into these (daemon/app/setup_overlay.h), so the link lines keep pointing from
// the app down to the renderer.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <glm/glm.hpp>

namespace lumar {

struct OverlayColor {
    uint8_t r = 255, g = 255, b = 255, a = 255; // sRGB code values as stored in the frame; a blends
    bool operator==(const OverlayColor&) const = default;
};

// A straight line between two points in OpenCV's pixel convention (pixel centres at integer
// coordinates, DESIGN.md §5), drawn `widthPx` thick with square ends, so that outlines close
// at their corners.
struct OverlayLine {
    glm::dvec2 from{0.0};
    glm::dvec2 to{0.0};
    OverlayColor color;
    float widthPx = 2.0f;
};

// One line of ASCII text whose cell box starts at pixel `topLeft` (rounded to the nearest
// pixel: its top-left pixel), glyphs `scale` times the font's pixels, over a filled box
// `background` (alpha 0: none) `padding` pixels wider on every side.
struct OverlayText {
    glm::dvec2 topLeft{0.0};
    std::string text;
    OverlayColor color;
    OverlayColor background{0, 0, 0, 0};
    int scale = 1;
    int padding = 2;
};

struct OverlayScene {
    std::vector<OverlayLine> lines;
    std::vector<OverlayText> texts; // drawn after, over the lines
    [[nodiscard]] bool empty() const { return lines.empty() && texts.empty(); }
    void clear()
    {
        lines.clear();
        texts.clear();
    }
};

} // namespace lumar
