// virtual_board_check: the host-side checks of the virtual board test (scripts/virtual-board.sh).
//
//   virtual_board_check scene CONFIG
//       Writes the fake camera's frame 0 of CONFIG's scene to frames/frame.png next to CONFIG,
//       the one image the guest plays in a loop (CONFIG names it: [camera] source = "images",
//       path = "frames").
//   virtual_board_check bars IMAGE --camera WxH
//       vivid's 75% colour bars, in order, in IMAGE (a headless still or a PPM screendump) where
//       a WxH camera image lands on it.
//   virtual_board_check object SCREEN CONFIG
//       The first object of CONFIG (a cube-shaped model with `size`, on a marker, no offset or
//       rotation) on SCREEN where the fake camera's ground-truth pose of frame 0 puts it: what
//       differs from frames/frame.png (scaled as the screen shows it) lies within the cube's
//       projected silhouette, covers most of it, and has its centroid within a few pixels of
//       the silhouette's. Writes the mask of differing pixels next to SCREEN as *.mask.png.
//
// Prints one line per check, the last the summary; exits 0 when the check passes, 1 when it
// fails, 2 for bad input.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <string>
#include <vector>

#include "capture/fake_camera.h"
#include "config/config.h"
#include "core/error.h"
#include "core/frame.h"
#include "output/frame_writer.h"
#include "system/screen_checks.h"

namespace {

using namespace lumar;
namespace fs = std::filesystem;

constexpr uint64_t kSceneFrame = 0;
// Where the screen differs from the camera frame is the object's silhouette less the pixels
// where the object happens to look like the frame behind it: the centroid moves a little.
constexpr double kCentroidTolerancePx = 3.0;
constexpr double kHullMarginPx = 2.0;        // around the ground-truth silhouette, screen pixels
constexpr double kMaxOutsideFraction = 0.02; // of the differing pixels, outside it
constexpr double kMinCoverage = 0.6;         // of the ground-truth silhouette, differing

bool byX(glm::dvec2 a, glm::dvec2 b)
{
    return a.x < b.x;
}
bool byY(glm::dvec2 a, glm::dvec2 b)
{
    return a.y < b.y;
}

fs::path framePath(const fs::path& config)
{
    return config.parent_path() / "frames" / "frame.png";
}

int scene(const fs::path& configFile)
{
    // The config names the folder as its image source, so it must exist before parsing.
    fs::create_directories(framePath(configFile).parent_path());
    const Config config = loadConfig(configFile);
    const FakeCamera camera(config.camera);
    Frame frame;
    camera.render(kSceneFrame, frame);
    writePng(framePath(configFile), frame.rgb);
    std::printf("scene: %dx%d fake camera frame %llu written to %s\n", frame.rgb.width, frame.rgb.height,
                static_cast<unsigned long long>(kSceneFrame), framePath(configFile).c_str());
    return kExitOk;
}

int bars(const fs::path& imageFile, int cameraWidth, int cameraHeight)
{
    const Image8 image = readImage(imageFile, 3);
    const test::BarsReport report = test::checkColourBars(image, cameraWidth, cameraHeight);
    std::printf("%s: %dx%d, %s\n", imageFile.filename().c_str(), image.width, image.height, report.summary.c_str());
    std::printf("%s\n", report.ok ? "colour bars in order" : "colour bars NOT found in order");
    return report.ok ? kExitOk : kExitRuntime;
}

int object(const fs::path& screenFile, const fs::path& configFile)
{
    const Config config = loadConfig(configFile);
    if (config.objects.empty())
        throw InputError(configFile.string() + ": no [[objects]] to look for");
    const ObjectConfig& object = config.objects.front();
    if (object.size <= 0.0 || !object.map.empty() || object.offset != glm::dvec3(0.0) || object.headingDeg != 0.0 ||
        object.rotationDeg != glm::dvec3(0.0))
        throw InputError(configFile.string() +
                         ": objects[0] must sit on a marker with `size`, no offset, heading or rotation");

    const Image8 screen = readImage(screenFile, 3);
    const Image8 played = readImage(framePath(configFile), 3);
    const FakeCamera camera(config.camera);
    if (played.width != camera.width() || played.height != camera.height())
        throw InputError(framePath(configFile).string() + ": not the scene's size (run `scene` first)");
    const std::vector<TagGroundTruth> truths = camera.groundTruth(kSceneFrame);
    const auto truth = std::find_if(truths.begin(), truths.end(), [&](const auto& t) { return t.id == object.marker; });
    if (truth == truths.end())
        throw InputError(configFile.string() + ": marker " + std::to_string(object.marker) + " is not a fake tag");

    // The cube (its bounding box centred on the tag, its lowest face on the tag's plane) is
    // convex: its silhouette is the convex hull of its projected corners.
    const test::ScreenRect rect = test::aspectFit(played.width, played.height, screen.width, screen.height);
    const double s = object.size;
    std::vector<glm::dvec2> corners;
    for (int corner = 0; corner < 8; ++corner) {
        const glm::dvec3 p((corner & 1 ? 0.5 : -0.5) * s, (corner & 2 ? 0.5 : -0.5) * s, corner & 4 ? s : 0.0);
        corners.push_back(test::cameraToScreen(rect, camera.intrinsics().project(truth->cameraFromMarker.apply(p))));
    }
    const std::vector<glm::dvec2> hull = test::convexHull(corners);
    const glm::dvec2 expected = test::polygonCentroid(hull);
    const double hullArea = test::polygonArea(hull);

    Image8 mask;
    const test::Silhouette silhouette = test::findSilhouette(screen, played, rect, 24, &mask);
    fs::path maskFile = screenFile;
    maskFile.replace_extension(".mask.png");
    writePng(maskFile, mask);
    long outside = 0;
    for (int y = 0; y < mask.height; ++y)
        for (int x = 0; x < mask.width; ++x)
            if (*mask.at(x, y) != 0 && !test::insideConvex(hull, {x, y}, kHullMarginPx))
                ++outside;
    const double coverage = double(silhouette.pixels - outside) / hullArea;
    const double errorPx = glm::length(silhouette.centroid - expected);

    std::printf("%s: %dx%d, camera %dx%d shown at (%.0f, %.0f) scale %.3f\n", screenFile.filename().c_str(),
                screen.width, screen.height, played.width, played.height, rect.offset.x, rect.offset.y, rect.scale.y);
    std::printf("object: %ld px differ from the camera frame, %ld of them outside the ground-truth silhouette "
                "(%.0f px, box %.0f..%.0f x %.0f..%.0f), which they cover to %.0f%%\n",
                silhouette.pixels, outside, hullArea, std::min_element(hull.begin(), hull.end(), byX)->x,
                std::max_element(hull.begin(), hull.end(), byX)->x, std::min_element(hull.begin(), hull.end(), byY)->y,
                std::max_element(hull.begin(), hull.end(), byY)->y, 100.0 * coverage);
    bool ok = true;
    if (coverage < kMinCoverage) {
        std::printf("the object does not fill its ground-truth silhouette (limit %.0f%%)\n", 100.0 * kMinCoverage);
        ok = false;
    }
    if (double(outside) > kMaxOutsideFraction * double(std::max(silhouette.pixels, 1L))) {
        std::printf("the screen differs from the camera frame outside the object (limit %.0f%%)\n",
                    100.0 * kMaxOutsideFraction);
        ok = false;
    }
    if (!(errorPx <= kCentroidTolerancePx))
        ok = false;
    std::printf("object centroid (%.1f, %.1f), ground truth (%.1f, %.1f): %.2f px off (limit %.1f): %s\n",
                silhouette.centroid.x, silhouette.centroid.y, expected.x, expected.y, errorPx, kCentroidTolerancePx,
                ok ? "ok" : "FAILED");
    return ok ? kExitOk : kExitRuntime;
}

void parseSize(const std::string& text, int& width, int& height)
{
    char x = 0;
    char extra = 0;
    if (std::sscanf(text.c_str(), "%d%c%d%c", &width, &x, &height, &extra) != 3 || x != 'x' || width < 16 ||
        height < 16 || width > 8192 || height > 8192)
        throw InputError("--camera: '" + text + "' is not WIDTHxHEIGHT");
}

constexpr const char* kUsage = "usage: virtual_board_check scene CONFIG\n"
                               "       virtual_board_check bars IMAGE --camera WxH\n"
                               "       virtual_board_check object SCREEN CONFIG\n";

} // namespace

int main(int argc, char** argv)
{
    const std::vector<std::string> args(argv + 1, argv + argc);
    try {
        if (args.size() == 2 && args[0] == "scene")
            return scene(args[1]);
        if (args.size() == 4 && args[0] == "bars" && args[2] == "--camera") {
            int width = 0, height = 0;
            parseSize(args[3], width, height);
            return bars(args[1], width, height);
        }
        if (args.size() == 3 && args[0] == "object")
            return object(args[1], args[2]);
        std::fputs(kUsage, stderr);
        return kExitBadInput;
    } catch (const InputError& e) {
        std::fprintf(stderr, "virtual_board_check: %s\n", e.what());
        return kExitBadInput;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "virtual_board_check: %s\n", e.what());
        return kExitRuntime;
    }
}
