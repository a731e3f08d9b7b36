#include "system/screen_checks.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace lumar::test {

ScreenRect aspectFit(int cameraWidth, int cameraHeight, int screenWidth, int screenHeight)
{
    ScreenRect r;
    const double fit = std::min(double(screenWidth) / cameraWidth, double(screenHeight) / cameraHeight);
    r.width = int(std::lround(cameraWidth * fit));
    r.height = int(std::lround(cameraHeight * fit));
    r.offset = {(screenWidth - r.width) / 2, (screenHeight - r.height) / 2};
    r.scale = {double(r.width) / cameraWidth, double(r.height) / cameraHeight};
    return r;
}

glm::dvec2 cameraToScreen(const ScreenRect& rect, glm::dvec2 cameraPixel)
{
    return rect.offset + (cameraPixel + 0.5) * rect.scale - 0.5;
}

BarsReport checkColourBars(const Image8& screen, int cameraWidth, int cameraHeight, double tolerance)
{
    constexpr double kOn = 0.75 * 255.0;
    static const std::array<glm::dvec3, 8> kBars = {glm::dvec3{kOn, kOn, kOn},
                                                    {kOn, kOn, 0},
                                                    {0, kOn, kOn},
                                                    {0, kOn, 0},
                                                    {kOn, 0, kOn},
                                                    {kOn, 0, 0},
                                                    {0, 0, kOn},
                                                    {0, 0, 0}};
    static const char* const kNames[] = {"white", "yellow", "cyan", "green", "magenta", "red", "blue", "black"};

    BarsReport report;
    const ScreenRect rect = aspectFit(cameraWidth, cameraHeight, screen.width, screen.height);
    // Rows 40%..90% of the picture: vivid writes its text overlay into the top lines.
    const int y0 = int(rect.offset.y + 0.40 * rect.height);
    const int y1 = int(rect.offset.y + 0.90 * rect.height);
    report.ok = true;
    std::string values, wrong;
    for (size_t bar = 0; bar < kBars.size(); ++bar) {
        const double barWidth = rect.width / 8.0;
        const int x0 = int(rect.offset.x + (double(bar) + 0.25) * barWidth);
        const int x1 = int(rect.offset.x + (double(bar) + 0.75) * barWidth);
        glm::dvec3 sum(0.0);
        long n = 0;
        for (int y = std::max(y0, 0); y < std::min(y1, screen.height); ++y)
            for (int x = std::max(x0, 0); x < std::min(x1, screen.width); ++x) {
                const uint8_t* p = screen.at(x, y);
                sum += glm::dvec3(p[0], p[1], p[2]);
                ++n;
            }
        const glm::dvec3 mean = n > 0 ? sum / double(n) : glm::dvec3(-1.0);
        report.means[bar] = mean;
        char text[64];
        std::snprintf(text, sizeof text, "%s%s %.0f/%.0f/%.0f", bar ? ", " : "", kNames[bar], mean.r, mean.g, mean.b);
        values += text;
        const glm::dvec3 d = glm::abs(mean - kBars[bar]);
        if (n == 0 || std::max({d.r, d.g, d.b}) > tolerance) {
            report.ok = false;
            wrong += std::string(wrong.empty() ? "" : ", ") + kNames[bar];
        }
    }
    report.summary = "bars (mean RGB): " + values + (wrong.empty() ? "" : "; not the 75% colour: " + wrong);
    return report;
}

Silhouette findSilhouette(const Image8& screen, const Image8& camera, const ScreenRect& rect, int tolerance,
                          Image8* mask)
{
    Silhouette s;
    if (mask != nullptr)
        *mask = Image8(screen.width, screen.height, 1);
    glm::dvec2 sum(0.0);
    s.min = {screen.width, screen.height};
    s.max = {-1, -1};
    const int xBegin = std::max(0, int(rect.offset.x)), yBegin = std::max(0, int(rect.offset.y));
    const int xEnd = std::min(screen.width, int(rect.offset.x) + rect.width);
    const int yEnd = std::min(screen.height, int(rect.offset.y) + rect.height);
    for (int y = yBegin; y < yEnd; ++y)
        for (int x = xBegin; x < xEnd; ++x) {
            // The camera pixel this screen pixel's centre falls in.
            const int cx = std::clamp(int(std::floor((x + 0.5 - rect.offset.x) / rect.scale.x)), 0, camera.width - 1);
            const int cy = std::clamp(int(std::floor((y + 0.5 - rect.offset.y) / rect.scale.y)), 0, camera.height - 1);
            const uint8_t* p = screen.at(x, y);
            bool background = true;
            for (int c = 0; c < 3 && background; ++c) {
                int lo = 255, hi = 0;
                for (int dy = -1; dy <= 1; ++dy)
                    for (int dx = -1; dx <= 1; ++dx) {
                        const int v = camera.at(std::clamp(cx + dx, 0, camera.width - 1),
                                                std::clamp(cy + dy, 0, camera.height - 1))[c];
                        lo = std::min(lo, v);
                        hi = std::max(hi, v);
                    }
                background = p[c] >= lo - tolerance && p[c] <= hi + tolerance;
            }
            if (background)
                continue;
            ++s.pixels;
            if (mask != nullptr)
                *mask->at(x, y) = 255;
            sum += glm::dvec2(x, y);
            s.min = glm::min(s.min, glm::ivec2(x, y));
            s.max = glm::max(s.max, glm::ivec2(x, y));
        }
    if (s.pixels > 0)
        s.centroid = sum / double(s.pixels);
    return s;
}

namespace {
double cross(glm::dvec2 o, glm::dvec2 a, glm::dvec2 b)
{
    return (a.x - o.x) * (b.y - o.y) - (a.y - o.y) * (b.x - o.x);
}
} // namespace

std::vector<glm::dvec2> convexHull(std::vector<glm::dvec2> points)
{
    // Andrew's monotone chain.
    std::sort(points.begin(), points.end(),
              [](glm::dvec2 a, glm::dvec2 b) { return a.x < b.x || (a.x == b.x && a.y < b.y); });
    if (points.size() < 3)
        return points;
    std::vector<glm::dvec2> hull(2 * points.size());
    size_t k = 0;
    for (size_t i = 0; i < points.size(); ++i) {
        while (k >= 2 && cross(hull[k - 2], hull[k - 1], points[i]) <= 0)
            --k;
        hull[k++] = points[i];
    }
    for (size_t i = points.size() - 1, lower = k + 1; i-- > 0;) {
        while (k >= lower && cross(hull[k - 2], hull[k - 1], points[i]) <= 0)
            --k;
        hull[k++] = points[i];
    }
    hull.resize(k - 1);
    return hull;
}

double polygonArea(const std::vector<glm::dvec2>& polygon)
{
    double twice = 0.0;
    for (size_t i = 0; i < polygon.size(); ++i)
        twice += cross(glm::dvec2(0.0), polygon[i], polygon[(i + 1) % polygon.size()]);
    return 0.5 * twice;
}

glm::dvec2 polygonCentroid(const std::vector<glm::dvec2>& polygon)
{
    glm::dvec2 sum(0.0);
    double twice = 0.0;
    for (size_t i = 0; i < polygon.size(); ++i) {
        const glm::dvec2 a = polygon[i], b = polygon[(i + 1) % polygon.size()];
        const double c = cross(glm::dvec2(0.0), a, b);
        sum += (a + b) * c;
        twice += c;
    }
    return sum / (3.0 * twice);
}

bool insideConvex(const std::vector<glm::dvec2>& hull, glm::dvec2 p, double margin)
{
    // Inside (or within `margin` of) every edge of a counter-clockwise polygon.
    for (size_t i = 0; i < hull.size(); ++i) {
        const glm::dvec2 a = hull[i], b = hull[(i + 1) % hull.size()];
        if (cross(a, b, p) / glm::length(b - a) < -margin)
            return false;
    }
    return !hull.empty();
}

} // namespace lumar::test
