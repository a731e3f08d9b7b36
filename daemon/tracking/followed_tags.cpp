#include "tracking/followed_tags.h"

#include <algorithm>
#include <cmath>

namespace lumar {
namespace {

// A window reaches this far past its tag's predicted corners: at least kMinRoiMargin pixels,
// and half the tag's own size (a tag moving fast between frames stays inside). With tight
// windows (TagTracker: while every scene tag is held), a tag seen on the last two frames gets
// kMinRoiMargin past the most its corners moved between them instead (a tag twice as fast
// stays inside). The detector's time grows with the window's area: car.toml's tag, ~220 px
// wide and moving ~5 px per frame, is searched in a ~320x300 px window, not a ~435x415 px one.
// A tag that jumps further is cut by the window's edge, and that frame is searched whole
// (TagTracker): it costs time, not the tag. Not while a scene tag is missing: then the windows
// are as wide as before, and a tag coming back next to a followed one is found in its window
// as before.
constexpr double kMinRoiMargin = 48.0;
// Windows closer than this are searched as one: two calls on touching windows cost more than
// one on their union, and a tag straddling the gap would be cut by both.
constexpr int kMergeGapPx = 16;
constexpr double kWindowEdgeClearance = 4.0;

glm::dvec2 centre(const std::array<glm::dvec2, 4>& corners)
{
    return 0.25 * (corners[0] + corners[1] + corners[2] + corners[3]);
}

bool nearOrOverlapping(const SearchWindow& a, const SearchWindow& b)
{
    return a.x0 <= b.x1 + kMergeGapPx && b.x0 <= a.x1 + kMergeGapPx && a.y0 <= b.y1 + kMergeGapPx &&
           b.y0 <= a.y1 + kMergeGapPx;
}

} // namespace

FollowedTags::FollowedTags(int width, int height, int align) : width_(width), height_(height), align_(align) {}

void FollowedTags::seen(const std::vector<TagDetection>& detections, uint64_t frame)
{
    std::vector<std::pair<int, int>> updated;
    for (const TagDetection& d : detections) {
        // Which followed copy of this id is it (an id may be seen several times)? The nearest
        // one not updated yet; a new copy when none is left.
        const glm::dvec2 at = centre(d.corners);
        auto best = tags_.end();
        double bestDistance = 1e300;
        int copies = 0;
        for (auto it = tags_.lower_bound({d.id, 0}); it != tags_.end() && it->first.first == d.id; ++it) {
            copies = std::max(copies, it->first.second + 1);
            if (std::find(updated.begin(), updated.end(), it->first) != updated.end())
                continue;
            const double distance = glm::length(centre(it->second.corners) - at);
            if (distance < bestDistance) {
                bestDistance = distance;
                best = it;
            }
        }
        const bool isNew = best == tags_.end();
        if (isNew)
            best = tags_.try_emplace({d.id, copies}).first;
        Tag& tag = best->second;
        // Velocity only from consecutive frames: after a gap the old one is stale.
        const bool consecutive = !isNew && tag.frame + 1 == frame;
        tag.velocity = consecutive ? at - centre(tag.corners) : glm::dvec2(0.0);
        tag.cornerMotion = -1.0;
        if (consecutive)
            for (size_t c = 0; c < 4; ++c)
                tag.cornerMotion = std::max(tag.cornerMotion, glm::length(d.corners[c] - tag.corners[c]));
        tag.corners = d.corners;
        tag.frame = frame;
        updated.push_back(best->first);
    }
}

void FollowedTags::predicted(int id, const std::array<glm::dvec2, 4>& corners, uint64_t frame)
{
    Tag& tag = tags_[{id, 0}];
    tag.velocity = glm::dvec2(0.0); // the map's pose moves it from now on
    tag.cornerMotion = -1.0;
    tag.corners = corners;
    tag.frame = frame;
}

std::vector<SearchWindow> FollowedTags::windows(uint64_t frame, bool tight)
{
    std::vector<SearchWindow> result;
    for (auto it = tags_.begin(); it != tags_.end();) {
        const Tag& tag = it->second;
        const uint64_t age = frame > tag.frame ? frame - tag.frame : 0;
        if (age > kLostTagFrames) {
            it = tags_.erase(it);
            continue;
        }
        const glm::dvec2 shift = tag.velocity * double(age);
        double minX = 1e300, minY = 1e300, maxX = -1e300, maxY = -1e300;
        for (const glm::dvec2& corner : tag.corners) {
            const glm::dvec2 c = corner + shift;
            minX = std::min(minX, c.x);
            minY = std::min(minY, c.y);
            maxX = std::max(maxX, c.x);
            maxY = std::max(maxY, c.y);
        }
        // The longer a tag goes unseen, the less sure its place: the margin grows by half its
        // predicted motion per frame missed (from the full margin: a tag unseen for a while may
        // have sped up).
        const double missed = age > 1 ? double(age - 1) : 0.0;
        double margin = std::max(kMinRoiMargin, 0.5 * std::max(maxX - minX, maxY - minY));
        if (tight && age <= 1 && tag.cornerMotion >= 0.0)
            margin = std::min(margin, kMinRoiMargin + tag.cornerMotion);
        margin += 0.5 * glm::length(tag.velocity) * missed;
        if (!(maxX + margin > 0.0 && maxY + margin > 0.0 && minX - margin < width_ && minY - margin < height_)) {
            it = tags_.erase(it); // predicted out of view
            continue;
        }
        const auto clampTo = [](double v, int hi) { return int(std::clamp(v, 0.0, double(hi))); };
        SearchWindow w{clampTo(std::floor(minX - margin), width_), clampTo(std::floor(minY - margin), height_),
                       clampTo(std::ceil(maxX + margin), width_), clampTo(std::ceil(maxY + margin), height_)};
        w.x0 = w.x0 / align_ * align_;
        w.y0 = w.y0 / align_ * align_;
        if (w.x1 > w.x0 && w.y1 > w.y0)
            result.push_back(w);
        ++it;
    }
    // Merge until no two windows are near each other (a handful of windows: quadratic is fine).
    for (bool merged = true; merged;) {
        merged = false;
        for (size_t i = 0; i < result.size() && !merged; ++i)
            for (size_t j = i + 1; j < result.size() && !merged; ++j)
                if (nearOrOverlapping(result[i], result[j])) {
                    result[i] = {std::min(result[i].x0, result[j].x0), std::min(result[i].y0, result[j].y0),
                                 std::max(result[i].x1, result[j].x1), std::max(result[i].y1, result[j].y1)};
                    result.erase(result.begin() + std::ptrdiff_t(j));
                    merged = true;
                }
    }
    return result;
}

bool wellInside(const std::vector<TagDetection>& detections, const SearchWindow& w, int width, int height)
{
    for (const TagDetection& d : detections)
        for (const glm::dvec2& c : d.corners) {
            if ((w.x0 > 0 && c.x < w.x0 + kWindowEdgeClearance) || (w.y0 > 0 && c.y < w.y0 + kWindowEdgeClearance) ||
                (w.x1 < width && c.x > w.x1 - kWindowEdgeClearance) ||
                (w.y1 < height && c.y > w.y1 - kWindowEdgeClearance))
                return false;
        }
    return true;
}

} // namespace lumar
