// The tags the region-of-interest search follows (DESIGN.md §5): every tag seen within the
// last kLostTagFrames frames, and every tag of a [[maps]] board whose place the board's pose
// predicts. Each gets a search window around its predicted corners, so that a tag missed once
// (low light, a blur spike, an occlusion) is looked for again on the very next frame, not only
// at the next scheduled full-frame search.
#pragma once

#include <array>
#include <cstdint>
#include <map>
#include <utility>
#include <vector>

#include <glm/glm.hpp>

#include "tracking/tag_tracker.h"

namespace lumar {

// A tag unseen for this many frames (1 s at 30 fps) is no longer looked for in a window of its
// own; the scheduled full-frame searches still find it when it comes back.
inline constexpr uint64_t kLostTagFrames = 30;

class FollowedTags {
public:
    // `align`: window origins are multiples of it (see TagTracker: the library's decimation
    // grid and threshold tiles then fall where a full-frame search puts them).
    FollowedTags(int width, int height, int align);

    // This frame's detections (frame numbers increase by one per detect() call).
    void seen(const std::vector<TagDetection>& detections, uint64_t frame);
    // A tag not detected at `frame` whose corners a map's pose predicts there.
    void predicted(int id, const std::array<glm::dvec2, 4>& corners, uint64_t frame);

    // The windows to search at `frame`: one around each followed tag's predicted corners,
    // merged where they overlap or nearly touch, clipped to the image; tags predicted wholly
    // outside the image are dropped. `tight`: the margins of the tags seen on the last two
    // frames follow their motion (followed_tags.cpp); otherwise every margin is at least half
    // its tag's size, and a tag entering the view next to a followed one is found in its window.
    [[nodiscard]] std::vector<SearchWindow> windows(uint64_t frame, bool tight = false);

    void clear() { tags_.clear(); }
    [[nodiscard]] bool empty() const { return tags_.empty(); }

private:
    struct Tag {
        std::array<glm::dvec2, 4> corners{};
        glm::dvec2 velocity{0.0}; // pixels per frame, from the last two consecutive sightings
        // The largest distance a corner moved between those two sightings (pixels per frame:
        // the centre's motion with the tag's turning and scaling); negative when unknown.
        double cornerMotion = -1.0;
        uint64_t frame = 0; // when seen (or predicted) there
    };
    int width_, height_, align_;
    std::map<std::pair<int, int>, Tag> tags_; // by id and copy (0: the only or leftmost one)
};

// True when every corner of every detection lies at least kWindowEdgeClearance pixels inside
// `w`'s edges that are not the image's own: a tag cut by a window's edge can still decode, with
// a wrong quad, and such a result is not trusted.
bool wellInside(const std::vector<TagDetection>& detections, const SearchWindow& w, int width, int height);

} // namespace lumar
