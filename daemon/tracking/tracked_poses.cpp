#include "tracking/tracked_poses.h"

namespace lumar {

PoseFilterSettings poseFilterSettings(const TrackingConfig& tracking)
{
    PoseFilterSettings settings;
    settings.minCutoffHz = tracking.filterMinCutoffHz;
    settings.beta = tracking.filterBeta;
    settings.rotationMinCutoffHz = tracking.filterRotationMinCutoffHz;
    settings.rotationBeta = tracking.filterRotationBeta;
    return settings;
}

TrackedPoses::TrackedPoses(const TrackingConfig& tracking)
    : filter_(tracking.filter), settings_(poseFilterSettings(tracking))
{
}

void TrackedPoses::update(const std::vector<TagDetection>& detections, const std::vector<MapDetection>& maps,
                          uint64_t sequence, int64_t timestampNs)
{
    for (const TagDetection& d : detections)
        if (d.hasPose)
            updateOne(d.id, d.cameraFromMarker, sequence, timestampNs);
    for (const MapDetection& map : maps)
        updateOne(mapKey(map.index), map.cameraFromMap, sequence, timestampNs);
}

void TrackedPoses::updateOne(int key, const Pose& measured, uint64_t sequence, int64_t timestampNs)
{
    auto [it, inserted] = markers_.try_emplace(key);
    Marker& marker = it->second;
    if (inserted)
        marker.filter = OneEuroPoseFilter(settings_);
    marker.measured = filter_ ? marker.filter.update(measured, timestampNs) : measured;
    marker.lastSeen = sequence;
}

Pose TrackedPoses::predicted(const Marker& marker, int64_t timestampNs) const
{
    // The filter extrapolates with its velocities; unfiltered poses stay as measured.
    return filter_ && marker.filter.initialised() ? marker.filter.predict(timestampNs) : marker.measured;
}

std::optional<TrackedPoses::Used> TrackedPoses::poseAt(int key, uint64_t sequence, int64_t timestampNs) const
{
    const auto it = markers_.find(key);
    if (it == markers_.end() || sequence - it->second.lastSeen > kMarkerHoldFrames)
        return std::nullopt;
    return Used{key, predicted(it->second, timestampNs), it->second.lastSeen};
}

std::vector<TrackedPoses::Used> TrackedPoses::all(uint64_t sequence, int64_t timestampNs) const
{
    std::vector<Used> result;
    for (const auto& [key, marker] : markers_)
        if (sequence - marker.lastSeen <= kMarkerHoldFrames)
            result.push_back({key, predicted(marker, timestampNs), marker.lastSeen});
    return result;
}

} // namespace lumar
