// lumar detect: AprilTag detection and per-tag pose on still images, one JSON object per
// image on stdout; with a config, the poses of its [[maps]] too; with --sequence, the images
// are video frames and the filtered poses are printed as well. An unreadable image is
// reported on stderr, the others are still processed, and the exit code is then 2.
#include <cmath>
#include <cstdio>
#include <memory>

#include "commands.h"
#include "config/config.h"
#include "core/error.h"
#include "output/frame_writer.h"
#include "tracking/calibration_io.h"
#include "tracking/detection_json.h"
#include "tracking/tag_map.h"
#include "tracking/tag_tracker.h"
#include "tracking/tracked_poses.h"

namespace lumar {
namespace {

struct DetectSetup {
    TrackingConfig tracking;
    TagSizes sizes;
    std::vector<TagMap> maps;
    std::vector<std::string> mapNames;
};

DetectSetup setupFor(const DetectCommandOptions& options)
{
    DetectSetup setup;
    if (options.config) {
        const Config config = loadConfig(*options.config);
        setup.tracking = config.tracking;
        for (const MarkerConfig& m : config.markers)
            setup.sizes.byId[m.id] = m.size;
        for (const MapConfig& map : config.maps) {
            setup.maps.push_back(makeTagMap(map));
            setup.mapNames.push_back(map.name);
        }
    }
    // Detection as the command line says; following and filtering as the config does.
    setup.tracking.family = options.family;
    setup.tracking.quadDecimate = options.decimate;
    setup.sizes.fallback = options.tagSize;
    return setup;
}

} // namespace

int detectCommand(const DetectCommandOptions& options)
{
    configureLogLevel(options.logLevel);
    const DetectSetup setup = setupFor(options);
    const auto& calibration = options.calibration;
    const CameraIntrinsics calibrated = calibration ? loadCalibration(*calibration) : CameraIntrinsics{};

    // One tracker for every image: building one builds the family's decoding tables (about
    // 0.45 s for tag36h11 with 2 correctable bits, measured here), far more than detecting in
    // a 720p image. reset() makes each image a still (no windows, no previous poses); in a
    // sequence the tracker follows the tags from frame to frame instead.
    std::unique_ptr<TagTracker> tracker;
    TrackedPoses tracked(setup.tracking);
    const double frameNs = 1e9 / options.fps;
    uint64_t frame = 0;
    int exitCode = kExitOk;
    for (const std::string& file : options.images) {
        try {
            const Image8 luma = readImage(file, 1);
            CameraIntrinsics k = calibration ? calibrated : defaultIntrinsics(luma.width, luma.height);
            if (k.width != luma.width || k.height != luma.height)
                throw InputError(file + ": image is " + std::to_string(luma.width) + "x" + std::to_string(luma.height) +
                                 " but " + (calibration ? *calibration + " is calibrated" : "the first image is") +
                                 " for " + std::to_string(k.width) + "x" + std::to_string(k.height));
            if (!tracker) {
                tracker = std::make_unique<TagTracker>(setup.tracking, k, setup.sizes);
                tracker->setMaps(setup.maps);
            } else if (!options.sequence) {
                tracker->reset(k);
            }
            const std::vector<TagDetection> detections = tracker->detect(luma);
            const std::vector<MapDetection> maps =
                setup.maps.empty() ? std::vector<MapDetection>{} : tracker->detectMaps(detections);
            Json line = detectionsJson(file, detections);
            if (!setup.maps.empty()) {
                Json list = Json::array();
                for (const MapDetection& map : maps)
                    list.push_back(mapDetectionJson(map));
                line["maps"] = std::move(list);
            }
            if (options.sequence) {
                const auto timestampNs = int64_t(std::llround(double(frame) * frameNs));
                tracked.update(detections, maps, frame, timestampNs);
                line["frame"] = frame;
                line["timestamp_ns"] = timestampNs;
                Json filtered = Json::array();
                for (const TrackedPoses::Used& used : tracked.all(frame, timestampNs))
                    filtered.push_back(trackedPoseJson(used, setup.mapNames));
                line["filtered"] = std::move(filtered);
            }
            std::printf("%s\n", jsonLine(line).c_str());
        } catch (const InputError& e) {
            std::fprintf(stderr, "lumar: %s\n", e.what());
            exitCode = kExitBadInput;
        }
        ++frame; // an unreadable frame still took its time slot
    }
    return exitCode;
}

} // namespace lumar
