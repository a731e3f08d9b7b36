// One frame's path (DESIGN.md §3): capture → tracking → scene → renderer. The pipeline owns
// one instance of each stage, built from a validated Config, and reuses every buffer from
// frame to frame.
#pragma once

#include <filesystem>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "capture/capture_source.h"
#include "config/config.h"
#include "core/camera_model.h"
#include "core/frame.h"
#include "detection_worker.h"
#include "exposure_meter.h"
#include "gles_renderer/gl/window_target.h"
#include "gles_renderer/ibl/dominant_light.h"
#include "gles_renderer/scene/scene_renderer.h"
#include "object_animation.h"
#include "tracking/one_euro_filter.h"
#include "tracking/tag_map.h"
#include "tracking/tag_tracker.h"
#include "tracking/tracked_poses.h"

namespace lumar {

struct StageTimes {
    double captureMs = 0, detectMs = 0, renderMs = 0, readbackMs = 0;
};

// What a reload kept of the running pipeline (Pipeline::applyReload), for the log.
struct ReloadSummary {
    bool keptRenderer = false;    // and its EGL/GL context
    bool keptTracker = false;     // and the markers' filtered poses
    bool keptEnvironment = false; // the environment map and its lighting
    size_t modelsBefore = 0, modelsAfter = 0;
};

// An object the renderer was given this frame: its transform exactly as handed over.
struct DrawnObject {
    int object = 0; // index in the config's [[objects]]
    int marker = 0; // a tag id, or TrackedPoses::mapKey() of a [[maps]] entry
    glm::dmat4 cameraFromModel{1.0};
};

struct FrameReport {
    uint64_t sequence = 0;
    int64_t timestampNs = 0; // the frame's timestamp (Frame::timestampNs)
    int64_t capturedNs = 0;  // when it was captured (Frame::capturedNs; 0: unknown)
    std::vector<TagDetection> detections;
    std::vector<MapDetection> maps;
    // The frame the detections come from (this one, except with background detection).
    uint64_t detectedSequence = 0;
    // The filtered poses the objects were placed with, predicted to poseTimeNs, for every tag
    // and map held (TrackedPoses::all), and the objects as the renderer received them.
    int64_t poseTimeNs = 0;
    std::vector<TrackedPoses::Used> poses;
    std::vector<std::string> mapNames; // the config's [[maps]] names, by index
    std::vector<DrawnObject> objects;
    int objectsDrawn = 0;
    StageTimes times;
    // Capture-to-present latency of the newest frame known to have been presented during
    // this step: from its capture (Frame::capturedNs) to its readback done (headless) or its
    // page flip (KMS, whose flip of the previous frame completes while this one is queued);
    // nullopt where nothing was known presented (the first KMS frame).
    std::optional<double> latencyMs;
};

// The renderer's options for `config`: its [rendering] with the board's GL quirks deciding
// what it leaves open (environment_maps = "auto", half-float-only).
RenderOptions renderOptionsFor(const Config& config);

class Pipeline {
public:
    // Opens the camera, loads calibration, models and environment, creates the GL context.
    // Throws InputError for bad files, RuntimeError for a platform failure.
    // `profile`: the renderer times its stages (waiting for the GPU between them), for bench.
    // `window`: present every frame there (a KMS display, which outlives the pipeline) instead
    // of reading it back; output() then stays empty.
    // `replayFrames` > 0: that many frames are captured before the first step and served
    // from memory (capture/replay_source.h), as `lumar bench --replay` measures.
    // `realTime`: frames are shown as they come (`lumar run`): the fake camera draws each
    // frame just in time for the pipeline, except on a software rasteriser, whose CPU it would
    // take (capture/prefetching_source.h). Cameras hand over their newest frame in any case.
    explicit Pipeline(const Config& config, bool profile = false, WindowTarget* window = nullptr, int replayFrames = 0,
                      bool realTime = false);
    [[nodiscard]] RenderStats renderStats() const;
    ~Pipeline();
    Pipeline(const Pipeline&) = delete;
    Pipeline& operator=(const Pipeline&) = delete;

    // A reload in place (DESIGN.md §7): applied to this pipeline, a new configuration keeps
    // the capture source, and keeps the renderer with its GL context, the tracker and the
    // environment map where it does not change them; models, objects, phantoms and filter
    // settings are replaced. It needs the same [camera] (board defaults included): a camera
    // change takes a new Pipeline.
    // What prepareReload() loaded and made, for applyReload().
    struct PreparedReload {
        Config config;
        CameraIntrinsics intrinsics;
        std::unique_ptr<TagTracker> tracker;           // null: the running one is kept
        std::vector<GltfModel> models;                 // config.objects' models, loaded
        std::optional<ImageF> environment;             // nullopt: the running map is kept
        std::optional<DominantLight> environmentLight; // `environment`'s, where the config needs it
        std::filesystem::file_time_type environmentWritten{};
        std::unique_ptr<SceneRenderer> renderer; // null: the running one is kept
    };
    // Whether `next` can be applied to this pipeline: its [camera] is the running one's.
    [[nodiscard]] bool keepsCamera(const Config& next) const { return next.camera == config_.camera; }
    // Loads and creates everything `next` needs that the running pipeline cannot keep: models,
    // environment map, calibration, tracker, and a renderer when its creation settings
    // changed. Throws InputError for bad input, RuntimeError for a platform failure; the
    // running pipeline is untouched either way (it keeps rendering meanwhile).
    [[nodiscard]] PreparedReload prepareReload(const Config& next) const;
    // Switches to the prepared configuration: nothing left to fail on input, only GL uploads.
    ReloadSummary applyReload(PreparedReload prepared);

    // Processes the next camera frame; false at the end of a finite source.
    bool step(FrameReport& report);

    // From now on detection runs on its own thread and step() never waits for it: each frame
    // is rendered with the newest detections available, the poses predicted to the frame's
    // expected display time. (`lumar run`; `lumar render` stays frame-exact.)
    void detectInBackground();

    // The setup view (setup_overlay.h) over every frame from the next step on; off, frames are
    // what the renderer composited, bit for bit. Starts as [output] overlay says; a reload
    // that changes that value sets it again.
    void setOverlay(bool on) { overlayOn_ = on; }
    [[nodiscard]] bool overlay() const { return overlayOn_; }
    // What the view's status line shows after the pipeline's own part (the run loop: the
    // measured frame rate, the camera's state).
    void setOverlayStatus(std::string text) { overlayStatus_ = std::move(text); }

    [[nodiscard]] const Image8& output() const { return output_; }
    [[nodiscard]] const Frame& cameraFrame() const { return frame_; }
    [[nodiscard]] const CameraIntrinsics& intrinsics() const { return intrinsics_; }
    [[nodiscard]] double fps() const { return capture_->fps(); }
    [[nodiscard]] const CaptureSource& captureSource() const { return *capture_; }
    // The capture runs at its own rate and hands over its newest frame: no need to pace.
    [[nodiscard]] bool capturePacesItself() const;
    // Frames the capture dropped for a newer one before the pipeline took them.
    [[nodiscard]] uint64_t framesDropped() const;

private:
    struct PlacedObject {
        ModelId model = -1;
        int marker = 0; // a tag id, or mapKey() of a [[maps]] entry
        glm::dmat4 markerFromModel{1.0};
        ObjectAnimation animation; // what plays (objects only)
    };

    // Adds the configured objects (`models` in config_.objects' order) and phantoms to the
    // renderer, which holds no models yet.
    void placeScene(const std::vector<GltfModel>& models);
    // Makes the renderer for frames of width x height and gives it the scene.
    void makeSceneRenderer(int width, int height, const std::vector<GltfModel>& models, const ImageF& environment);
    // Draws the scene once from a made-up view and forgets it (see the constructor).
    void warmUp(const CameraIntrinsics& intrinsics);
    // Gives the renderer the dominant light: the first configured [[lights]] entry that casts
    // shadows, else the one derived from the environment map (derivedLight_).
    void applyLight();
    // The receiver-only ground under each marker's objects ([shadows] ground; ground_plane.h).
    void placeGrounds(const std::vector<GltfModel>& models);
    void drawSetupOverlay(const FrameReport& report);
    // Returns the free pages loading left in malloc's heaps to the system, and drops the
    // code only loading ran from the resident set (working_set.h).
    static void releaseLoadingMemory();
    // Once the first frames have compiled every shader variant: drops the code only start-up
    // ran (the shader compilers) from the resident set.
    static void releaseStartupMemory();
    // Seconds of scene time at the current frame, what animations play at: since the first
    // frame's capture timestamp with `realTime` (`lumar run`), else the frame number / fps
    // (`lumar render`, `lumar bench`: the same on every run).
    [[nodiscard]] double sceneSeconds();

    Config config_;
    bool profile_ = false;
    bool realTime_ = false;
    std::optional<int64_t> firstTimestampNs_; // with realTime_: the scene clock's start
    std::vector<ClipTime> clips_;             // per-object scratch
    WindowTarget* window_ = nullptr;
    std::unique_ptr<CaptureSource> capture_;
    CameraIntrinsics intrinsics_;
    std::unique_ptr<TagTracker> tracker_;
    // After tracker_: destroyed (joined) before the tracker it uses.
    std::unique_ptr<DetectionWorker> worker_;
    DetectionWorker::Result latest_;
    double displayLatencyMs_ = 0.0; // running mean of render + readback: capture to display
    std::unique_ptr<SceneRenderer> renderer_;
    // The environment file's modification time when it was loaded: a reload with the same
    // [environment] keeps the map unless the file changed on disk.
    std::filesystem::file_time_type environmentWritten_{};
    std::vector<PlacedObject> objects_;
    std::vector<PlacedObject> phantoms_; // markerFromModel scales the unit cube to the box
    std::vector<PlacedObject> grounds_;  // receiver-only planes under objects ([shadows] ground)
    // The environment map's own light (not yet scaled by its intensity), computed where the
    // configuration needs it.
    std::optional<DominantLight> derivedLight_;
    TrackedPoses tracked_; // the markers' and maps' filtered poses
    std::vector<DrawItem> drawItems_;
    // The camera image's brightness against its first frames' ([environment] match_exposure).
    ExposureMeter exposureMeter_;
    Frame frame_;
    int64_t previousCapturedNs_ = 0; // the frame presented before frame_ (KMS latency)
    int framesRendered_ = 0;         // up to kStartupFrames: when releaseStartupMemory runs
    Image8 output_;
    bool overlayOn_ = false;
    std::string overlayStatus_;
    OverlayScene overlay_; // reused from frame to frame
};

} // namespace lumar
