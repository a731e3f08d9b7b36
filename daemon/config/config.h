// lumar's configuration: one TOML file (DESIGN.md §1). Parsing validates everything — unknown
// keys, wrong types, out-of-range values, missing files — and throws InputError whose message
// is one line "FILE:LINE: what is wrong". Relative paths in the file are resolved against the
// file's directory; the built-in default resolves them against the installed asset directory.
#pragma once

#include <cstdint>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <glm/glm.hpp>

#include "config/board_profile.h"
#include "gles_renderer/assets/gltf_model.h"
#include "gles_renderer/assets/material_overrides.h"

namespace lumar {

struct FakeTagConfig {
    int id = 0;
    double size = 0.16;       // metres, black border to black border
    glm::dvec2 position{0.0}; // centre on the fake table-top, metres
    bool operator==(const FakeTagConfig&) const = default;
};

// [[camera.fake_objects]]: a real object standing on the fake camera's table, placed in a
// fake tag's frame (the world frame moved to the tag's centre). The camera draws it, shaded by
// the environment, and bakes its shadow into the table (capture/fake_objects.h).
struct FakeObjectConfig {
    std::string shape = "box";     // "box" | "cylinder" (upright)
    int tag = 0;                   // the fake tag whose frame it stands in
    glm::dvec3 size{0.1};          // metres along x, y, z; a cylinder: diameter x = y, height z
    glm::dvec2 offset{0.0};        // its footprint's centre from the tag's centre, metres
    double headingDeg = 0.0;       // degrees about z, counter-clockwise seen from above
    glm::dvec3 color{0.5};         // linear albedo, each in [0, 1]; unused with a texture
    std::filesystem::path texture; // PNG or JPEG (sRGB) mapped over each face, instead of color
    bool operator==(const FakeObjectConfig&) const = default;
};

// [camera.controls]: camera controls applied when the camera opens (V4L2 controls, or
// libcamera's: capture/libcamera/libcamera_controls.h). A key left out leaves the camera's own
// setting alone.
struct CameraControlsConfig {
    static constexpr int kAuto = -1;  // "auto" in the file
    std::optional<int> exposureUs;    // microseconds, or kAuto (automatic exposure)
    std::optional<int> gain;          // the device's own gain units
    std::optional<int> whiteBalanceK; // kelvin, or kAuto (automatic white balance)
    std::optional<int> powerLineHz;   // anti-flicker filter: 0 (off), 50 or 60

    [[nodiscard]] bool empty() const { return !exposureUs && !gain && !whiteBalanceK && !powerLineHz; }
    bool operator==(const CameraControlsConfig&) const = default;
};

struct CameraConfig {
    std::string source = "fake";        // "fake" | "y4m" | "images" | "v4l2" | "libcamera"
    std::filesystem::path path;         // y4m file or image folder (source y4m/images)
    std::string device = "/dev/video0"; // v4l2: the device node; libcamera: a camera id (else the first)
    int timeoutMs = 2000;               // v4l2, libcamera: no frame for this long is an error
    int buffers = 4;                    // v4l2: MMAP buffers; libcamera: frame buffers requested
    std::string format = "auto";        // v4l2: "auto" (NV12 > YUYV > MJPEG > GREY) or one of them;
                                        // libcamera: "auto" (NV12 > YUYV), "nv12" or "yuyv"
    std::string convert = "auto";       // v4l2, libcamera NV12/YUYV: YCbCr to RGB in the renderer ("gpu"), "cpu",
                                        // or "auto" (gpu unless the GLES implementation is a software rasteriser)
    std::string zeroCopy = "auto";      // v4l2, libcamera with convert gpu: "auto" (the camera's buffers lent to the
                                        // renderer, imported as dmabufs where EGL can) or "off" (the planes copied)
    CameraControlsConfig controls;      // sources v4l2 and libcamera
    int width = 1280;                   // fake: the size; v4l2: the size requested; files: their own
    int height = 720;
    double fps = 30.0;
    bool loop = true;                  // file sources: start again at the end
    std::filesystem::path calibration; // OpenCV FileStorage YAML; empty: ideal default
    // Fake source scene.
    uint64_t seed = 1;
    double noiseSigma = 2.0; // sensor noise, code values
    std::vector<FakeTagConfig> fakeTags{FakeTagConfig{}};
    std::vector<FakeObjectConfig> fakeObjects;
    double exposure = 1.0; // code = 255 sRGB(clamp(exposure * linear radiance)); > 0
    // What surrounds the fake table: [environment]'s hdr and intensity, copied here when the
    // source is fake so the camera shows the world the virtual objects are lit by; empty: the
    // plain room of old.
    std::filesystem::path fakeEnvironment;
    double fakeEnvironmentIntensity = 1.0;
    // A reload compares the running configuration with the new one part by part, to keep
    // what did not change (the camera, the GL context).
    bool operator==(const CameraConfig&) const = default;
};

struct TrackingConfig {
    std::string family = "tag36h11";
    double quadDecimate = 2.0;
    double quadSigma = 0.0;
    bool refineEdges = true;
    double decodeSharpening = 0.25;
    int threads = 2;         // >= 2: windows on two detectors at once, see tracking/tag_tracker.cpp
    bool roi = true;         // search near the last detections first (full frame as fallback)
    int fullFrameEvery = 10; // with roi: a full-frame search at least this often (new tags)
    // With roi: a cheap search of the whole frame at coarseDecimate every coarseEvery frames
    // between full-frame searches (0: none); a tag it finds that no window holds brings the
    // full-frame search at once (a tag re-entering the view), see tracking/tag_tracker.cpp.
    int coarseEvery = 3; // measured: leave_reenter recall 0.952 -> 1.000 for +18% CPU (every 1: +73%)
    double coarseDecimate = 4.0;
    int maxBitErrors = 2; // bit errors corrected in the scene's tags; other ids decode error-free (scene_families.h)
    bool filter = true;   // One-Euro pose filtering (tracking/one_euro_filter.h)
    double filterMinCutoffHz = 0.3;
    double filterBeta = 40.0;
    double filterRotationMinCutoffHz = 0.3;
    double filterRotationBeta = 8.0;
    bool operator==(const TrackingConfig&) const = default;
};

struct MarkerConfig {
    int id = 0;
    double size = 0.16; // metres, black border to black border
    bool operator==(const MarkerConfig&) const = default;
};

// [[maps]]: a board or a set of tags with a known layout, solved jointly for one pose
// (DESIGN.md §5). Each tag's frame (core/pose.h) sits in the map frame at `position`,
// turned by `rotationDeg` about x, then y, then z (R = Rz * Ry * Rx, as objects turn).
struct MapTagConfig {
    int id = 0;
    double size = 0.16;          // metres, black border to black border
    glm::dvec3 position{0.0};    // the tag's centre in the map frame, metres
    glm::dvec3 rotationDeg{0.0}; // degrees; all zero: the tag frame is the map frame
    bool operator==(const MapTagConfig&) const = default;
};

struct MapConfig {
    std::string name;
    std::vector<MapTagConfig> tags;
    bool operator==(const MapConfig&) const = default;
};

struct ObjectConfig {
    std::string name;
    std::filesystem::path model;         // glTF 2.0 (.gltf or .glb), or "builtin:sphere" / "builtin:cube"
    std::filesystem::path materials;     // optional sidecar TOML of Lafortune materials
    MaterialOverrides materialOverrides; // what `materials` says, read with the configuration
    std::string material;                // optional preset for every material (e.g. "chrome")
    int marker = 0;                      // id of the marker it sits on
    std::string map;                     // or the name of the [[maps]] entry it sits on (then `marker` is unused)
    glm::dvec3 offset{0.0};              // metres, marker frame
    double headingDeg = 0.0;             // degrees about the marker's normal (+z), counter-clockwise from above
    glm::dvec3 rotationDeg{0.0};         // degrees, Rz·Ry·Rx in the upright frame, before heading
                                         // (app/object_placement.h has the whole composition)
    double scale = 1.0;                  // uniform; or set `size` to fit the longest side
    double size = 0.0;                   // metres; > 0 overrides scale
    // Which of the model's glTF animations plays (app/object_animation.h): "" (not given: the
    // first, so a model exported with an animation moves), "all", "none", or a name; or, with
    // animationIndex >= 0, that index. Checked against the model when it is loaded.
    std::string animation;
    int animationIndex = -1;
    // The line of `animation` in the file, for check-config's message (0: not given).
    int animationLine = 0;
    bool loop = true;   // false: the clip holds its last pose once played
    double speed = 1.0; // clip seconds per scene second, >= 0 (0: the clip's first pose)
};

struct EnvironmentConfig {
    std::filesystem::path hdr; // equirectangular Radiance .hdr
    double intensity = 1.0;    // scales the .hdr (the camera's part is in the camera's own units)
    // Where the real environment comes from (DESIGN.md §6.5): "hdr" (the file), "camera" (built
    // from the camera frames as the camera turns, unseen directions the image's mean; no hdr
    // needed) or "camera+hdr" (the same, unseen directions from the hdr, which it needs).
    std::string source = "hdr";
    // The virtual objects follow the camera image's brightness (app/exposure_meter.h). On by
    // default: webcams and libcamera run auto-exposure unless told otherwise, and without it
    // every exposure step the camera takes leaves the objects visibly brighter or darker than
    // the scene around them. Turn it off for a camera with fixed exposure whose view moves
    // between bright and dark parts of the room (the meter cannot tell that from exposure).
    bool matchExposure = true;
    bool operator==(const EnvironmentConfig&) const = default;
};

// A proxy of a real object (DESIGN.md §6.5): a shape placed on a marker. It hides virtual
// objects behind it and appears in their environment maps carrying the camera image where
// the camera sees it, in its colour elsewhere.
struct PhantomConfig {
    std::string name;
    int marker = 0;
    // box (default), plane (in the marker plane), cylinder (axis along the marker's normal)
    // or mesh (a glTF model, stood on the marker like an object: app/object_placement.h).
    std::string shape = "box";
    // Metres. box: along the marker's x, y, z (z out of the tag); plane: x, y (z unused);
    // cylinder: the diameters along x and y, the height along z; mesh: x = the longest side
    // (`size = 0.3` in the file; 0: as authored).
    glm::dvec3 size{0.1};
    // Metres, marker frame: the centre of a box, plane or cylinder; a mesh's offset as an
    // object's (its footprint centre, its lowest point on the plane z = offset.z).
    glm::dvec3 offset{0.0};
    double headingDeg = 0.0;               // degrees about the marker's normal, counter-clockwise from above
    std::filesystem::path model;           // mesh: .gltf or .glb, or "builtin:sphere" / "builtin:cube"
    std::shared_ptr<const GltfModel> mesh; // mesh: the model, read with the configuration
    glm::dvec3 color{0.5};                 // linear diffuse albedo, each in [0, 1]
};

// [[lights]]: the dominant light, when the real environment's own (derived from its SH,
// gles_renderer/ibl/dominant_light.h) is not the one wanted (DESIGN.md §6.5). The light is a
// share of the environment's light, not added to it: shadows remove it where it is blocked.
struct LightConfig {
    std::string type = "directional";
    glm::dvec3 direction{0.0, 0.0, 1.0}; // towards the light, in the frame of the marker the first object
                                         // stands on (z up, as objects are placed); unit length
    glm::dvec3 color{1.0};               // linear, each in [0, 1]
    double intensity = 1.0;              // irradiance on a surface facing the light, in the environment
                                         // map's radiance units times steradians (a uniform sky of radiance
                                         // L gives a floor irradiance of pi L)
    bool shadow = true;                  // whether it casts shadows (the renderer shadows one light)
    bool operator==(const LightConfig&) const = default;
};

// [shadows]: shadow maps of the dominant light and contact darkening (DESIGN.md §6.5).
struct ShadowsConfig {
    bool enabled = true;
    int mapSize = 1024;    // shadow-map texels per side, a power of two 256..4096
    double softness = 1.5; // PCF kernel radius, shadow-map texels
    // Resolution the darkening of the real surfaces is shaded at: "full", "half" or "quarter"
    // of the frame's width and height (half costs a quarter of full; the edges blur a pixel).
    std::string resolution = "half";
    bool ground = true; // a receiver-only plane on the marker's plane under objects that stand
                        // on no phantom, so their shadows and contact darkening show on the table
    bool operator==(const ShadowsConfig&) const = default;
};

// [rendering.lens]: bloom and glare streaks from the virtual objects' bright light (DESIGN.md
// §6.5; gles_renderer's LensOptions says what each does). Off by default.
struct LensConfig {
    bool enabled = false;
    double threshold = 1.0; // radiance x exposure above which light blooms, 0..1000
    bool bloom = true;
    double bloomIntensity = 0.5; // 0..16
    double bloomRadius = 32.0;   // output pixels, 2..1024
    bool glare = false;
    int glareStreaks = 4;        // rays per bright spot, 2..16
    double glareLength = 96.0;   // output pixels, 4..1024
    double glareIntensity = 0.3; // 0..16
    double glareAngle = 0.0;     // degrees of the first ray from image right towards down, -360..360
    bool operator==(const LensConfig&) const = default;
};

// The paper's per-object environment maps (DESIGN.md §6.1).
struct RenderingConfig {
    // auto: every_frame, or budget on a board with the software-renderer GL quirk
    std::string environmentMaps = "auto"; // auto | every_frame | every_k | budget | on_change | off
    int environmentMapEvery = 2;          // every_k: each object every k-th frame
    double environmentMapBudgetMs = 8.0;  // budget: milliseconds per frame
    int environmentMapSize = 64;          // px per cube face, a power of two 16..256
    bool phantomsShowCamera = true;       // phantoms carry the camera image in the maps
    LensConfig lens;                      // [rendering.lens]
    bool operator==(const RenderingConfig&) const = default;
};

struct OutputConfig {
    std::string sink = "headless"; // "headless" (files) | "kms" (a DRM/KMS display) | "window" (X11) | "none"
    // kms: the device and output; "auto"/empty take the board profile's [display] choice.
    std::string drmDevice = "auto";   // "auto" (the board's drm_drivers, else any) or /dev/dri/cardN
    std::string connector;            // e.g. "HDMI-A-1"; empty: the board's, else the first connected
    std::string plane = "auto";       // "auto" (the board's) | "primary" | "overlay"
    std::string mode = "auto";        // "auto" (the connector's preferred) or "WIDTHxHEIGHT"
    std::string kmsApi = "auto";      // "auto" (atomic where the driver has it) | "legacy"
    std::filesystem::path path;       // .png or .y4m for `lumar run`; empty: no file (kms: the fallback)
    std::filesystem::path statusPath; // `lumar run` state as JSON, e.g. /run/lumar/status.json
    bool overlay = false;             // the setup view over every frame (app/setup_overlay.h); `lumar run --overlay`
    bool operator==(const OutputConfig&) const = default;
};

struct Config {
    std::filesystem::path sourceFile; // empty for the built-in default
    std::string logLevel = "info";
    std::optional<BoardProfile> board; // `board = "..."`: its camera values are [camera]'s defaults
    CameraConfig camera;
    TrackingConfig tracking;
    std::vector<MarkerConfig> markers;
    std::vector<MapConfig> maps;
    std::vector<ObjectConfig> objects;
    std::vector<PhantomConfig> phantoms;
    EnvironmentConfig environment;
    std::vector<LightConfig> lights;
    ShadowsConfig shadows;
    RenderingConfig rendering;
    OutputConfig output;

    // The size of marker `id`, or 0 when the config does not know that marker.
    [[nodiscard]] double markerSize(int id) const;
};

// Parses and validates TOML text. `fileName` is used in messages, relative paths resolve
// against `baseDir`. Throws InputError.
Config parseConfig(std::string_view text, const std::filesystem::path& fileName, const std::filesystem::path& baseDir);

// Reads and parses a file. Throws InputError (including "cannot read").
Config loadConfig(const std::filesystem::path& file);

// The built-in default: fake camera, shipped model, HDR map and calibration.
Config defaultConfig();
std::string_view defaultConfigText();

// Where the shipped assets live: $LUMAR_ASSET_DIR, else next to the executable
// (../share/lumar when installed), else the source tree's daemon/assets.
std::filesystem::path assetDirectory();

} // namespace lumar
