// Convex polygons in the plane, for the fake objects' outlines: their shadows on the table
// and their silhouettes' bounds on screen.
#pragma once

#include <algorithm>
#include <cmath>
#include <vector>

#include <glm/glm.hpp>

namespace lumar {

// Andrew's monotone chain: the convex hull of `points`, counter-clockwise (y up).
inline std::vector<glm::vec2> convexHull(std::vector<glm::vec2> points)
{
    std::sort(points.begin(), points.end(),
              [](const glm::vec2& a, const glm::vec2& b) { return a.x < b.x || (a.x == b.x && a.y < b.y); });
    const auto cross = [](const glm::vec2& o, const glm::vec2& a, const glm::vec2& b) {
        return (a.x - o.x) * (b.y - o.y) - (a.y - o.y) * (b.x - o.x);
    };
    std::vector<glm::vec2> hull(2 * points.size());
    size_t k = 0;
    for (size_t i = 0; i < points.size(); ++i) {
        while (k >= 2 && cross(hull[k - 2], hull[k - 1], points[i]) <= 0.0f) {
            --k;
        }
        hull[k++] = points[i];
    }
    for (size_t i = points.size() - 1, lower = k + 1; i-- > 0;) {
        while (k >= lower && cross(hull[k - 2], hull[k - 1], points[i]) <= 0.0f) {
            --k;
        }
        hull[k++] = points[i];
    }
    hull.resize(k > 1 ? k - 1 : k);
    return hull;
}

// Where the horizontal line at `y` crosses convex polygon `hull`: [left, right], or
// left > right when it misses.
inline glm::vec2 convexSpanAt(const std::vector<glm::vec2>& hull, float y)
{
    float left = INFINITY;
    float right = -INFINITY;
    for (size_t e = 0; e < hull.size(); ++e) {
        const glm::vec2& a = hull[e];
        const glm::vec2& b = hull[(e + 1) % hull.size()];
        if ((a.y <= y && y <= b.y) || (b.y <= y && y <= a.y)) {
            if (a.y == b.y) {
                left = std::min({left, a.x, b.x});
                right = std::max({right, a.x, b.x});
            } else {
                const float x = a.x + (y - a.y) * (b.x - a.x) / (b.y - a.y);
                left = std::min(left, x);
                right = std::max(right, x);
            }
        }
    }
    return {left, right};
}

} // namespace lumar
