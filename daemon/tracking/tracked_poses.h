// The poses objects are drawn with (DESIGN.md §5): per tag id and per [[maps]] board, the
// measured pose filtered over time (tracking/one_euro_filter.h) and predicted to the time the
// frame is shown. The pipeline places its objects with them, `lumar render --trace` records
// them and `lumar detect --sequence` prints them, so that what is drawn can be scored.
#pragma once

#include <cstdint>
#include <map>
#include <optional>
#include <vector>

#include "config/config.h"
#include "core/pose.h"
#include "tracking/one_euro_filter.h"
#include "tracking/tag_map.h"
#include "tracking/tag_tracker.h"

namespace lumar {

// A marker missed for a few frames (motion blur, a hand passing) keeps its last pose so
// objects do not flicker; after that they disappear rather than float in a stale place.
inline constexpr uint64_t kMarkerHoldFrames = 5;

// [tracking]'s filter settings.
PoseFilterSettings poseFilterSettings(const TrackingConfig& tracking);

class TrackedPoses {
public:
    // Tags are keyed by id, maps by mapKey(index in the config's order): no tag id takes those.
    static int mapKey(int mapIndex) { return -1 - mapIndex; }
    static bool isMapKey(int key) { return key < 0; }
    static int mapIndex(int key) { return -1 - key; }

    explicit TrackedPoses(const TrackingConfig& tracking = {});

    // One detection result (of the frame `sequence`, captured at `timestampNs`): every posed
    // tag and every map found updates its filter.
    void update(const std::vector<TagDetection>& detections, const std::vector<MapDetection>& maps, uint64_t sequence,
                int64_t timestampNs);

    struct Used {
        int key = 0;
        Pose cameraFromMarker; // filtered and predicted (as measured with the filter off)
        uint64_t lastSeen = 0; // the frame it was last measured in
    };
    // The pose of `key` to draw frame `sequence` with, shown at `timestampNs`: the filter's
    // prediction; nullopt when never seen or not for more than kMarkerHoldFrames frames.
    [[nodiscard]] std::optional<Used> poseAt(int key, uint64_t sequence, int64_t timestampNs) const;
    // Every key poseAt() gives a pose for, ascending (maps first).
    [[nodiscard]] std::vector<Used> all(uint64_t sequence, int64_t timestampNs) const;

    void clear() { markers_.clear(); }

private:
    struct Marker {
        Pose measured; // the last measurement, filtered when filtering is on
        uint64_t lastSeen = 0;
        OneEuroPoseFilter filter;
    };
    void updateOne(int key, const Pose& measured, uint64_t sequence, int64_t timestampNs);
    [[nodiscard]] Pose predicted(const Marker& marker, int64_t timestampNs) const;

    bool filter_ = true;
    PoseFilterSettings settings_;
    std::map<int, Marker> markers_;
};

} // namespace lumar
