// The virtual board test's screen checks on synthetic screens: each finds what is there, and
// fails on what a broken display path would show.
#include <cmath>

#include <gtest/gtest.h>

#include "system/screen_checks.h"

namespace lumar::test {
namespace {

constexpr uint8_t kOn = 191; // 75% of 255
const uint8_t kBars[8][3] = {{kOn, kOn, kOn}, {kOn, kOn, 0}, {0, kOn, kOn}, {0, kOn, 0},
                             {kOn, 0, kOn},   {kOn, 0, 0},   {0, 0, kOn},   {0, 0, 0}};

Image8 colourBars(int width, int height, const int order[8])
{
    Image8 image(width, height, 3);
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x) {
            const uint8_t* c = kBars[order[x * 8 / width]];
            // vivid's text overlay: white glyph-like speckles in the top lines.
            const bool text = y < height / 6 && (x * 7 + y * 3) % 5 == 0;
            for (int k = 0; k < 3; ++k)
                image.at(x, y)[k] = text ? 255 : c[k];
        }
    return image;
}

// Bilinear resampling of `camera` into a `rect` of a black screen: what a GL scaler does.
Image8 showOnScreen(const Image8& camera, int screenWidth, int screenHeight)
{
    const ScreenRect rect = aspectFit(camera.width, camera.height, screenWidth, screenHeight);
    Image8 screen(screenWidth, screenHeight, 3);
    for (int y = 0; y < screenHeight; ++y)
        for (int x = 0; x < screenWidth; ++x) {
            const double u = (x + 0.5 - rect.offset.x) / rect.scale.x - 0.5;
            const double v = (y + 0.5 - rect.offset.y) / rect.scale.y - 0.5;
            if (u < -0.5 || v < -0.5 || u > camera.width - 0.5 || v > camera.height - 0.5)
                continue;
            const int u0 = std::clamp(int(std::floor(u)), 0, camera.width - 1);
            const int v0 = std::clamp(int(std::floor(v)), 0, camera.height - 1);
            const int u1 = std::min(u0 + 1, camera.width - 1), v1 = std::min(v0 + 1, camera.height - 1);
            const double fu = std::clamp(u - u0, 0.0, 1.0), fv = std::clamp(v - v0, 0.0, 1.0);
            for (int c = 0; c < 3; ++c) {
                const double top = camera.at(u0, v0)[c] * (1 - fu) + camera.at(u1, v0)[c] * fu;
                const double bottom = camera.at(u0, v1)[c] * (1 - fu) + camera.at(u1, v1)[c] * fu;
                screen.at(x, y)[c] = uint8_t(std::lround(top * (1 - fv) + bottom * fv));
            }
        }
    return screen;
}

// A busy camera image: a fine checkerboard with a gradient, the worst case for a scaler.
Image8 texturedCamera(int width, int height)
{
    Image8 image(width, height, 3);
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x) {
            const bool dark = ((x / 6) + (y / 6)) % 2 == 0;
            image.at(x, y)[0] = dark ? 20 : 230;
            image.at(x, y)[1] = uint8_t(x * 255 / width);
            image.at(x, y)[2] = dark ? 200 : 40;
        }
    return image;
}

void fillSquare(Image8& image, int x0, int y0, int side, const uint8_t rgb[3])
{
    for (int y = y0; y < y0 + side; ++y)
        for (int x = x0; x < x0 + side; ++x)
            for (int c = 0; c < 3; ++c)
                image.at(x, y)[c] = rgb[c];
}

TEST(AspectFit, LetterboxesAndMapsPixelCentres)
{
    const ScreenRect same = aspectFit(640, 480, 1024, 768);
    EXPECT_DOUBLE_EQ(same.scale.x, 1.6);
    EXPECT_EQ(same.offset, glm::dvec2(0.0));
    const ScreenRect wide = aspectFit(640, 480, 1280, 720); // pillarboxed
    EXPECT_DOUBLE_EQ(wide.scale.y, 1.5);
    EXPECT_EQ(wide.width, 960);
    EXPECT_EQ(wide.offset, glm::dvec2(160.0, 0.0));
    // Camera pixel 0 covers screen [160, 161.5): its centre is at 160.75 - 0.5 in centre terms.
    EXPECT_NEAR(cameraToScreen(wide, {0.0, 0.0}).x, 160.25, 1e-12);
    // 1280x800 fits 1066.67 px: whole pixels, the left bar the smaller half (as a blit does).
    const ScreenRect odd = aspectFit(640, 480, 1280, 800);
    EXPECT_EQ(odd.width, 1067);
    EXPECT_EQ(odd.offset, glm::dvec2(106.0, 0.0));
    EXPECT_DOUBLE_EQ(odd.scale.x, 1067.0 / 640.0);
    EXPECT_DOUBLE_EQ(odd.scale.y, 800.0 / 480.0);
    EXPECT_NEAR(cameraToScreen(aspectFit(640, 480, 640, 480), {10.0, 20.0}).y, 20.0, 1e-12);
}

TEST(ColourBars, FoundInOrderAtCameraSizeAndScaled)
{
    const int order[8] = {0, 1, 2, 3, 4, 5, 6, 7};
    const Image8 camera = colourBars(640, 480, order);
    EXPECT_TRUE(checkColourBars(camera, 640, 480).ok) << checkColourBars(camera, 640, 480).summary;
    for (const auto& [w, h] : {std::pair{1024, 768}, {1280, 720}, {1280, 1024}, {1280, 800}}) {
        const BarsReport report = checkColourBars(showOnScreen(camera, w, h), 640, 480);
        EXPECT_TRUE(report.ok) << w << "x" << h << ": " << report.summary;
    }
}

TEST(ColourBars, WrongOrderOrNothingFails)
{
    const int swapped[8] = {0, 1, 3, 2, 4, 5, 6, 7}; // green before cyan
    const BarsReport report = checkColourBars(colourBars(640, 480, swapped), 640, 480);
    EXPECT_FALSE(report.ok);
    EXPECT_NE(report.summary.find("not the 75% colour: cyan, green"), std::string::npos) << report.summary;
    EXPECT_FALSE(checkColourBars(Image8(1024, 768, 3), 640, 480).ok); // a black screen
    // The bars shown 1:1 in the middle of a bigger screen are not where an aspect-fit sink
    // puts them: the check must not pass by accident.
    const int order[8] = {0, 1, 2, 3, 4, 5, 6, 7};
    const Image8 camera = colourBars(640, 480, order);
    Image8 centred(1024, 768, 3);
    for (int y = 0; y < 480; ++y)
        for (int x = 0; x < 640; ++x)
            for (int c = 0; c < 3; ++c)
                centred.at(x + 192, y + 144)[c] = camera.at(x, y)[c];
    EXPECT_FALSE(checkColourBars(centred, 640, 480).ok);
}

TEST(Silhouette, ScaledBackgroundIsNotAnObject)
{
    const Image8 camera = texturedCamera(320, 240);
    for (const auto& [w, h] : {std::pair{320, 240}, {1024, 768}, {800, 480}, {1280, 800}}) {
        const Image8 screen = showOnScreen(camera, w, h);
        const Silhouette s = findSilhouette(screen, camera, aspectFit(320, 240, w, h));
        EXPECT_EQ(s.pixels, 0) << w << "x" << h;
    }
}

TEST(Silhouette, CentroidAndBoxOfAnObject)
{
    Image8 camera = texturedCamera(320, 240);
    Image8 withObject = camera;
    const uint8_t grey[3] = {128, 128, 128}; // inside the checkerboard's channel ranges but not all
    const uint8_t orange[3] = {250, 140, 0};
    fillSquare(withObject, 100, 60, 40, orange);
    fillSquare(withObject, 110, 70, 20, grey);
    const ScreenRect rect = aspectFit(320, 240, 1024, 768);
    Image8 mask;
    const Silhouette s = findSilhouette(showOnScreen(withObject, 1024, 768), camera, rect, 24, &mask);
    const glm::dvec2 expected = cameraToScreen(rect, {119.5, 79.5});
    EXPECT_LT(glm::length(s.centroid - expected), 1.0) << s.centroid.x << "," << s.centroid.y;
    EXPECT_NEAR(double(s.pixels), 40.0 * 40.0 * rect.scale.x * rect.scale.y,
                0.05 * 40 * 40 * rect.scale.x * rect.scale.y);
    EXPECT_GE(s.min.x, int(cameraToScreen(rect, {99.0, 0.0}).x));
    EXPECT_LE(s.max.x, int(cameraToScreen(rect, {141.0, 0.0}).x));
    ASSERT_EQ(mask.width, 1024);
    EXPECT_EQ(*mask.at(int(expected.x), int(expected.y)), 255);
    EXPECT_EQ(*mask.at(5, 5), 0);
}

TEST(Silhouette, ShiftedBackgroundIsFoundEverywhere)
{
    const Image8 camera = texturedCamera(320, 240);
    Image8 shifted(320, 240, 3);
    for (int y = 0; y < 240; ++y)
        for (int x = 0; x < 320; ++x)
            for (int c = 0; c < 3; ++c)
                shifted.at(x, y)[c] = camera.at(std::min(x + 3, 319), y)[c];
    const Silhouette s = findSilhouette(shifted, camera, aspectFit(320, 240, 320, 240));
    EXPECT_GT(s.pixels, 320 * 240 / 8); // every checker edge moved by more than the 3x3 range
}

TEST(ConvexHull, OfAProjectedBox)
{
    // A square's corners with points inside and on its edges: the hull is the four corners.
    const std::vector<glm::dvec2> hull =
        convexHull({{10, 10}, {30, 10}, {20, 15}, {30, 40}, {10, 40}, {20, 10}, {25, 30}});
    ASSERT_EQ(hull.size(), 4u);
    EXPECT_DOUBLE_EQ(polygonArea(hull), 600.0);
    EXPECT_NEAR(polygonCentroid(hull).x, 20.0, 1e-12);
    EXPECT_NEAR(polygonCentroid(hull).y, 25.0, 1e-12);
    // A triangle's area centroid is the mean of its corners.
    const std::vector<glm::dvec2> triangle = convexHull({{0, 0}, {6, 0}, {0, 9}});
    EXPECT_NEAR(polygonCentroid(triangle).x, 2.0, 1e-12);
    EXPECT_NEAR(polygonCentroid(triangle).y, 3.0, 1e-12);
    EXPECT_TRUE(insideConvex(hull, {11, 39}));
    EXPECT_FALSE(insideConvex(hull, {9, 20}));
    EXPECT_TRUE(insideConvex(hull, {9, 20}, 1.5));
    EXPECT_FALSE(insideConvex(hull, {20, 42}, 1.5));
}

} // namespace
} // namespace lumar::test
