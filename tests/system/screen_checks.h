// What the virtual board test (scripts/virtual-board.sh) checks in a screen image (a QEMU
// screendump) or a headless still: vivid's colour bars in order, and a virtual object's
// silhouette against the camera frame it was drawn on. The camera image is assumed shown
// aspect-fit and centred (letterboxed or pillarboxed when the aspects differ), the way a
// display sink shows a camera frame on a screen of another size; a still has the camera's
// own size and maps 1:1.
#pragma once

#include <array>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "core/image.h"

namespace lumar::test {

// Where a camera image lands on the screen: screen = offset + camera * scale, in continuous
// coordinates where pixel (0,0) covers [0,1]^2. The rectangle is whole pixels (as a blit's
// is), so the scales differ slightly when the fitted size rounds.
struct ScreenRect {
    glm::dvec2 offset{0.0};
    glm::dvec2 scale{1.0};
    int width = 0; // of the image on the screen, pixels
    int height = 0;
};

ScreenRect aspectFit(int cameraWidth, int cameraHeight, int screenWidth, int screenHeight);

// A camera pixel position (OpenCV convention: pixel centres at integers) on the screen, in the
// same convention.
glm::dvec2 cameraToScreen(const ScreenRect& rect, glm::dvec2 cameraPixel);

// vivid's default test pattern, 75% colour bars: white, yellow, cyan, green, magenta, red,
// blue, black, each an eighth of the width.
struct BarsReport {
    bool ok = false;
    std::array<glm::dvec3, 8> means{}; // mean RGB of each bar's sampled middle
    std::string summary;               // one line: the means, and what is wrong if anything
};
// Each bar's mean colour (sampled in its middle half, below vivid's text overlay) must be
// within `tolerance` code values of the 75% colour in every channel.
BarsReport checkColourBars(const Image8& screen, int cameraWidth, int cameraHeight, double tolerance = 40.0);

// The pixels of `screen` (3 channels) inside `rect` that are not the camera image: a channel
// outside the range of the 3x3 camera pixels around where it maps, widened by `tolerance`
// (the range holds every interpolation a scaler may use between them).
struct Silhouette {
    long pixels = 0;
    glm::dvec2 centroid{0.0};  // screen pixel coordinates, centres at integers
    glm::ivec2 min{0}, max{0}; // bounding box
};
// With `mask`: also a 1-channel image of the screen's size, 255 where a pixel differs.
Silhouette findSilhouette(const Image8& screen, const Image8& camera, const ScreenRect& rect, int tolerance = 24,
                          Image8* mask = nullptr);

// The silhouette of a convex object (a box) is the convex hull of its projected corners.
// Vertices in positive orientation (interior to the left of each edge in x-right, y-up terms),
// no repeated or collinear points.
std::vector<glm::dvec2> convexHull(std::vector<glm::dvec2> points);
glm::dvec2 polygonCentroid(const std::vector<glm::dvec2>& polygon); // of its area
double polygonArea(const std::vector<glm::dvec2>& polygon);
bool insideConvex(const std::vector<glm::dvec2>& hull, glm::dvec2 p, double margin = 0.0);

} // namespace lumar::test
