// lumar detect: AprilTag detection and per-tag pose on still images, one JSON object per
// image on stdout. An unreadable image is reported on stderr, the others are still
// processed, and the exit code is then 2.
#include <cstdio>

#include "command_line.h"
#include "commands.h"
#include "config/config.h"
#include "core/error.h"
#include "core/log.h"
#include "output/frame_writer.h"
#include "tracking/calibration_io.h"
#include "tracking/detection_json.h"
#include "tracking/tag_tracker.h"

namespace lumar {
namespace {

constexpr const char* kHelp = R"(usage: lumar detect --tag-size M [--calib FILE] [--family NAME] [--decimate D]
                    [--log-level SPEC] IMAGE...

Detects AprilTags and prints, per image, one line:
  {"file":..., "detections":[{"id":..,"corners":[[x,y]x4],"R":[[..]x3],"t":[..]}]}
Corners are in the AprilTag library's order, in OpenCV's pixel convention (pixel centres at
integer coordinates). R and t map the tag frame (x right, y up, z out of the tag, metres)
into the camera frame. Without --calib an ideal camera with a 70 degree horizontal field of
view is assumed.
  --tag-size M   tag side in metres, black border to black border
  --family NAME  tag family (default tag36h11)
  --decimate D   quad_decimate (default 1: full resolution, best for stills)
)";

} // namespace

int detectCommand(const Args& args)
{
    const CommandLine cl(args, {{"tag-size"}, {"calib"}, {"family"}, {"decimate"}, {"log-level"}});
    if (cl.helpRequested()) {
        std::fputs(kHelp, stdout);
        return kExitOk;
    }
    if (!cl.has("tag-size"))
        throw UsageError("--tag-size M is required");
    if (cl.positional().empty())
        throw UsageError("no IMAGE given");
    if (!log::configure(cl.value("log-level").value_or("warn")))
        throw UsageError("bad --log-level");

    TrackingConfig tracking;
    tracking.family = cl.value("family").value_or("tag36h11");
    tracking.quadDecimate = cl.number("decimate", 1.0, 1.0, 8.0);
    TagSizes sizes;
    sizes.fallback = cl.number("tag-size", 0.0, 1e-4, 100.0);
    const auto calibration = cl.value("calib");
    const CameraIntrinsics calibrated = calibration ? loadCalibration(*calibration) : CameraIntrinsics{};

    int exitCode = kExitOk;
    for (const std::string& file : cl.positional()) {
        try {
            const Image8 luma = readImage(file, 1);
            CameraIntrinsics k = calibration ? calibrated : defaultIntrinsics(luma.width, luma.height);
            if (k.width != luma.width || k.height != luma.height)
                throw InputError(file + ": image is " + std::to_string(luma.width) + "x" + std::to_string(luma.height) +
                                 " but " + *calibration + " is calibrated for " + std::to_string(k.width) + "x" +
                                 std::to_string(k.height));
            TagTracker tracker(tracking, k, sizes);
            const std::string line = detectionsToJson(file, tracker.detect(luma));
            std::printf("%s\n", line.c_str());
        } catch (const InputError& e) {
            std::fprintf(stderr, "lumar: %s\n", e.what());
            exitCode = kExitBadInput;
        }
    }
    return exitCode;
}

} // namespace lumar
