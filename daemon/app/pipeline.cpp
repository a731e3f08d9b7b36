#include "pipeline.h"

#include <algorithm>
#include <chrono>
#include <stdexcept>
#include <tuple>

#include <glm/gtc/matrix_transform.hpp>
#include <malloc.h>

#include "capture/factory/capture_factory.h"
#include "capture/prefetching_source.h"
#include "capture/replay_source.h"
#include "core/environment_frame.h"
#include "core/error.h"
#include "core/log.h"
#include "core/monotonic_clock.h"
#include "gles_renderer/assets/builtin_shapes.h"
#include "gles_renderer/assets/environment_map.h"
#include "gles_renderer/assets/gltf_model.h"
#include "gles_renderer/assets/material_overrides.h"
#include "gles_renderer/gl/gl_probe.h"
#include "ground_plane.h"
#include "object_placement.h"
#include "phantom_model.h"
#include "setup_overlay.h"
#include "tracking/calibration_io.h"
#include "working_set.h"

namespace lumar {
namespace {

// glibc's mmap threshold while the constructor loads: large transient blocks (file bytes,
// decoded textures, the proxy models' copies, upload staging) are mapped on their own, so
// freeing one hands its pages back at once. Left dynamic, the threshold rises to the first
// large block freed and the later ones fragment the heap, where malloc_trim cannot return
// what live blocks share pages with (issue 18, car.toml --replay: resident 238 -> 228 MB).
constexpr int kLoadingMmapThreshold = 256 * 1024;
// Once loaded: glibc's dynamic ceiling (32 MiB on 64 bits), so the blocks libapriltag
// allocates per detection (0.3-1.8 MB at 720p) stay in their arena instead of costing an
// mmap, a munmap and their page faults every frame.
constexpr int kRunningMmapThreshold = 32 * 1024 * 1024;
// Once loaded: the free memory glibc keeps at the top of the main heap before it hands it back.
// Setting the mmap threshold fixes the trim threshold at its 128 KiB default instead of letting
// it follow, so the large blocks llvmpipe frees every frame (inside glDrawElements and its
// scene handling) shrank the heap (brk, whose unmapping interrupts the other core to flush its
// TLB) and the next frame faulted the same pages back: car.toml with bloom, replayed, 33-108
// page faults a frame, ~1 at 4 MiB or more (8 MiB: margin). Resident memory: +2 MiB, peak
// unchanged.
constexpr int kRunningTrimThreshold = 8 * 1024 * 1024;

// glibc's malloc arenas: one, shared by every thread. By default each thread that meets a
// locked arena gets its own (up to 8 per core), and each keeps its own free memory resident:
// the detection worker's arena alone held ~5 MB of apriltag's freed blocks (issue 18,
// car.toml --replay: peak resident 188.5 -> 184 MB). The per-thread caches (tcache) still
// serve the small blocks without taking the lock; the rasteriser's threads hardly allocate.
constexpr int kMallocArenas = 1;

// The largest material texture side on a software rasteriser, which keeps every texture with
// its mips in process memory: CesiumMilkTruck's 2048² base colour alone holds 22 MB as RGBA8
// with mips, 5.6 MB at 1024², 1.4 MB at 512². At 1280x720 the truck covers a few hundred
// pixels, so the sampler reads the 512² level or smaller anyway: car.toml's `lumar render`
// (20 frames) differs from the 1024² cap by at most 6 code values (mean 0.002), and its peak
// resident memory falls by 4 MB (issue 18).
constexpr int kSoftwareMaterialTextureLimit = 512;

// The frames after which start-up is over: llvmpipe compiles a program's variants when it is
// first drawn with a state, and the car scene draws all of its in the first frame (the shadow
// map, the environment maps, the blended pass); two more leave room for a pass that waits
// for a detection. A variant compiled later still works: it faults back what it needs.
constexpr int kStartupFrames = 3;

double millisecondsSince(std::chrono::steady_clock::time_point start)
{
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
}

CameraIntrinsics intrinsicsFor(const CameraConfig& camera, int width, int height)
{
    if (camera.calibration.empty())
        return defaultIntrinsics(width, height);
    CameraIntrinsics k = loadCalibration(camera.calibration);
    if (k.width != width || k.height != height)
        throw InputError(camera.calibration.string() + ": calibrated for " + std::to_string(k.width) + "x" +
                         std::to_string(k.height) + " but the camera delivers " + std::to_string(width) + "x" +
                         std::to_string(height));
    return k;
}

TagSizes tagSizesFor(const Config& config)
{
    TagSizes sizes;
    for (const MarkerConfig& m : config.markers)
        sizes.byId[m.id] = m.size;
    return sizes;
}

std::unique_ptr<TagTracker> makeTracker(const Config& config, const CameraIntrinsics& intrinsics)
{
    auto tracker = std::make_unique<TagTracker>(config.tracking, intrinsics, tagSizesFor(config));
    std::vector<TagMap> maps;
    for (const MapConfig& map : config.maps)
        maps.push_back(makeTagMap(map));
    tracker->setMaps(std::move(maps));
    return tracker;
}

bool sameIntrinsics(const CameraIntrinsics& a, const CameraIntrinsics& b)
{
    return a.width == b.width && a.height == b.height && a.fx == b.fx && a.fy == b.fy && a.cx == b.cx && a.cy == b.cy &&
           a.distortion == b.distortion;
}

// The object's model with its materials: a file or a built-in shape, then the sidecar's
// Lafortune materials, then the preset for every material.
GltfModel loadObjectModel(const ObjectConfig& object)
{
    const std::string model = object.model.string();
    GltfModel loaded = model.starts_with(kBuiltinModelPrefix)
                           ? makeBuiltinShape(std::string_view(model).substr(kBuiltinModelPrefix.size()))
                           : loadGltfModel(object.model);
    if (!object.materials.empty())
        applyMaterialOverrides(loaded, object.materialOverrides);
    if (!object.material.empty()) {
        MaterialOverrides everything;
        everything.materials["*"].preset = object.material;
        applyMaterialOverrides(loaded, everything);
    }
    (void)resolveObjectAnimation(object, loaded); // an unknown animation is bad input now, not later
    return loaded;
}

std::vector<GltfModel> loadObjectModels(const Config& config)
{
    std::vector<GltfModel> models;
    models.reserve(config.objects.size());
    for (const ObjectConfig& object : config.objects)
        models.push_back(loadObjectModel(object));
    return models;
}

bool boardHasQuirk(const Config& config, std::string_view quirk)
{
    return config.board && config.board->hasQuirk(quirk);
}

// GL_RENDERER of this machine's GLES, asked once; empty without EGL (the renderer will say so
// when it is created).
const std::string& glRendererName()
{
    static const std::string name = [] {
        try {
            return probeGl().glRenderer;
        } catch (const RuntimeError&) {
            return std::string();
        }
    }();
    return name;
}

bool isSoftwareRasteriser(const std::string& renderer)
{
    return renderer.find("llvmpipe") != std::string::npos || renderer.find("softpipe") != std::string::npos ||
           renderer.find("swrast") != std::string::npos;
}

// What the camera is opened with once the board has had its say: no zero-copy on a board
// with the no-dma-buf-import quirk, and camera.convert = "auto" decided — YCbCr to RGB on the
// GPU unless the GLES implementation is a software rasteriser, where the full-screen
// conversion pass costs more (measured on llvmpipe, 2 cores: 30 -> 25 fps) than the CPU
// conversion it saves.
CameraConfig withConversionDecided(CameraConfig camera, const Config& config)
{
    if (boardHasQuirk(config, "no-dma-buf-import") && camera.zeroCopy != "off") {
        LUMAR_LOG(App, Info) << "board " << config.board->name << ": no dma-buf import, camera frames are uploaded";
        camera.zeroCopy = "off";
    }
    if (camera.convert != "auto" || (camera.source != "v4l2" && camera.source != "libcamera"))
        return camera;
    const std::string renderer = glRendererName();
    const bool software = isSoftwareRasteriser(renderer);
    camera.convert = software || renderer.empty() ? "cpu" : "gpu";
    LUMAR_LOG(App, Info) << "camera.convert = auto: converting YCbCr on the "
                         << (camera.convert == "gpu" ? "GPU" : "CPU") << " (renderer "
                         << (renderer.empty() ? "unknown" : renderer) << ")";
    return camera;
}

// A dim neutral environment for configs without an HDR map.
ImageF neutralEnvironment()
{
    ImageF env(8, 4, 3);
    std::fill(env.data.begin(), env.data.end(), 0.5f);
    return env;
}

// When the file was last written; a default time for the built-in environment (or a file
// that cannot be read, which loading reports).
std::filesystem::file_time_type environmentWritten(const EnvironmentConfig& environment)
{
    std::error_code ec;
    const auto written = environment.hdr.empty() ? std::filesystem::file_time_type{}
                                                 : std::filesystem::last_write_time(environment.hdr, ec);
    return ec ? std::filesystem::file_time_type{} : written;
}

EnvironmentSource environmentSourceFor(const EnvironmentConfig& environment)
{
    return environment.source == "camera"       ? EnvironmentSource::Camera
           : environment.source == "camera+hdr" ? EnvironmentSource::CameraOverHdr
                                                : EnvironmentSource::Hdr;
}

ImageF loadEnvironment(const EnvironmentConfig& environment)
{
    return environment.hdr.empty() ? neutralEnvironment() : loadHdrImage(environment.hdr);
}

// Whether `config` takes its dominant light from the environment map (no [[lights]]).
bool needsDerivedLight(const Config& config)
{
    return config.shadows.enabled && config.lights.empty();
}

// The renderer for `config`; sameRendererSetup() compares what this reads, keep them in step.
std::unique_ptr<SceneRenderer> makeRenderer(const Config& config, int width, int height, bool profile,
                                            const WindowTarget* window)
{
    RenderOptions options = renderOptionsFor(config);
    // A software rasteriser without a board profile saying so caps its textures too.
    if (options.materialTextureLimit == 0 && isSoftwareRasteriser(glRendererName()))
        options.materialTextureLimit = kSoftwareMaterialTextureLimit;
    options.profile = profile;
    if (window)
        options.display = window->eglDisplay();
    return SceneRenderer::create(width, height, options);
}

// Whether a renderer made for `running` serves `next` (the output size is the camera's,
// which a reload in place keeps): what is fixed when it is created, the GL context with it.
// The sink and the board decide on which display and how the context is made: every [output]
// setting but the file paths, and the board's display and GL quirks, take a new one.
bool sameRendererSetup(const Config& running, const Config& next)
{
    const auto display = [](const Config& c) {
        OutputConfig output = c.output;
        output.path.clear();
        output.statusPath.clear();
        const BoardProfile board = c.board.value_or(BoardProfile{});
        return std::tuple(output, board.glQuirks, board.display.drmDrivers, board.display.connector,
                          board.display.plane, board.display.modifiers);
    };
    const auto shadows = [](const Config& c) {
        return std::tuple(c.shadows.enabled, c.shadows.mapSize, c.shadows.softness, c.shadows.resolution);
    };
    return running.rendering == next.rendering && shadows(running) == shadows(next) &&
           display(running) == display(next);
}

} // namespace

// The board's GL quirks (board/README.md) decide what the configuration leaves open.
RenderOptions renderOptionsFor(const Config& config)
{
    const RenderingConfig& rendering = config.rendering;
    RenderOptions options;
    EnvironmentMapOptions& maps = options.environmentMaps;
    std::string schedule = rendering.environmentMaps;
    if (schedule == "auto")
        schedule = boardHasQuirk(config, "software-renderer") ? "budget" : "every_frame";
    maps.dynamic = schedule != "off";
    maps.policy = schedule == "every_k"     ? EnvironmentMapPolicy::EveryKFrames
                  : schedule == "budget"    ? EnvironmentMapPolicy::Budget
                  : schedule == "on_change" ? EnvironmentMapPolicy::OnChange
                                            : EnvironmentMapPolicy::EveryFrame;
    maps.ibl.halfFloatOnly = boardHasQuirk(config, "half-float-only");
    maps.everyK = rendering.environmentMapEvery;
    maps.budgetMs = rendering.environmentMapBudgetMs;
    maps.ibl.mirrorSize = rendering.environmentMapSize;
    options.shadows.enabled = config.shadows.enabled;
    options.shadows.mapSize = config.shadows.mapSize;
    options.shadows.softness = float(config.shadows.softness);
    options.shadows.receiverScale = config.shadows.resolution == "full"      ? 1
                                    : config.shadows.resolution == "quarter" ? 4
                                                                             : 2;
    maps.phantomsShowCamera = rendering.phantomsShowCamera;
    if (boardHasQuirk(config, "software-renderer"))
        options.materialTextureLimit = kSoftwareMaterialTextureLimit;
    const LensConfig& lens = rendering.lens;
    options.lens = {.enabled = lens.enabled,
                    .threshold = float(lens.threshold),
                    .bloom = lens.bloom,
                    .bloomIntensity = float(lens.bloomIntensity),
                    .bloomRadius = float(lens.bloomRadius),
                    .glare = lens.glare,
                    .glareStreaks = lens.glareStreaks,
                    .glareLength = float(lens.glareLength),
                    .glareIntensity = float(lens.glareIntensity),
                    .glareAngle = float(lens.glareAngle)};
    return options;
}

Pipeline::Pipeline(const Config& config, bool profile, WindowTarget* window, int replayFrames, bool realTime)
    : config_(config), profile_(profile), realTime_(realTime), window_(window), overlayOn_(config.output.overlay)
{
    // Constructed first, so destroyed last: once the loaded models and maps below are freed.
    struct ReleaseWhenLoaded {
        // mallopt only tunes: a value it refused leaves glibc's defaults, which still work.
        ReleaseWhenLoaded()
        {
            // Before the capture, detection and rasteriser threads start and make arenas.
            (void)mallopt(M_ARENA_MAX, kMallocArenas);
            (void)mallopt(M_MMAP_THRESHOLD, kLoadingMmapThreshold);
        }
        ~ReleaseWhenLoaded()
        {
            (void)mallopt(M_MMAP_THRESHOLD, kRunningMmapThreshold);
            (void)mallopt(M_TRIM_THRESHOLD, kRunningTrimThreshold);
            releaseLoadingMemory();
        }
    } releaseWhenLoaded;
    tracked_ = TrackedPoses(config_.tracking);
    const CameraConfig camera = withConversionDecided(config_.camera, config_);
    // Load every file before creating the GL context, so bad input is reported as such even
    // on a machine without EGL.
    std::vector<GltfModel> models = loadObjectModels(config_);
    environmentWritten_ = environmentWritten(config_.environment);
    ImageF environment = loadEnvironment(config_.environment);
    // The resident set peaks while the renderer compiles its programs, on top of the loaded
    // files: the loaders' code (glTF, Draco, HDR, PNG decoding, ~17 MB) leaves it first
    // (issue 18: car.toml --replay, peak 145 -> 134 MB while the renderer is made).
    (void)dropCleanFilePages();
    // The first frame compiles the programs' variants (on llvmpipe the compiler's code, ~34 MB
    // of libLLVM, is resident while it runs). Drawn before the camera opens, with the loaded
    // files freed, it does not add to what they and the camera hold (the fake camera's lit
    // table and frames, a replay's frames): where the source's size is known before it opens,
    // the renderer is made, its first frame drawn from a made-up view and forgotten, and the
    // compilers' code dropped (issue 18, car.toml with bloom, 2 + 3 interleaved runs: peak
    // 157.6-158.1 -> 132.8-134.3 MiB live, 140.6 -> 122.8 MiB replayed).
    bool loaded = true;
    if (camera.source == "fake") {
        makeSceneRenderer(camera.width, camera.height, models, environment);
        models = {};
        environment = {};
        loaded = false;
        releaseLoadingMemory();
        warmUp(intrinsicsFor(config_.camera, camera.width, camera.height));
        releaseLoadingMemory();
    }
    std::unique_ptr<CaptureSource> source = openCaptureSource(camera);
    // Frames served from memory are lent, not copied (replay_source.h): not worth a thread,
    // and served just when asked for they carry no wait in a hand-over slot into the latency.
    if (replayFrames > 0)
        capture_ = std::make_unique<ReplaySource>(std::move(source), replayFrames);
    else {
        // The fake camera drawn just in time for the pipeline competes with a software
        // rasteriser for the CPU at the end of each frame: on llvmpipe with 2 cores, car.toml's
        // `lumar run` fell from ~24 s to ~41 s for 120 frames (medians of 5, load 7) while its
        // latency p50 fell from 315-820 to 165-255 ms; there it keeps its frames in order.
        const bool justInTime = realTime && !isSoftwareRasteriser(glRendererName());
        capture_ = std::make_unique<PrefetchingSource>(std::move(source),
                                                       prefetchOptionsFor(config_.camera.source, justInTime));
    }
    intrinsics_ = intrinsicsFor(config_.camera, capture_->width(), capture_->height());
    tracker_ = makeTracker(config_, intrinsics_);
    if (!renderer_ || renderer_->width() != capture_->width() || renderer_->height() != capture_->height()) {
        if (!loaded) { // the source's frames are not the size it was configured for
            models = loadObjectModels(config_);
            environment = loadEnvironment(config_.environment);
        }
        makeSceneRenderer(capture_->width(), capture_->height(), models, environment);
    }
}

void Pipeline::makeSceneRenderer(int width, int height, const std::vector<GltfModel>& models, const ImageF& environment)
{
    renderer_.reset(); // one GL context at a time
    renderer_ = makeRenderer(config_, width, height, profile_, window_);
    // Creating the renderer compiled its programs: the compiler's code (libLLVM on llvmpipe,
    // ~56 MB) need not stay resident while the models upload; the first frame's shader
    // variants fault back what they run (issue 18: car.toml's peak 175 -> 142 MB).
    (void)dropCleanFilePages();
    renderer_->setEnvironment(environment, float(config_.environment.intensity));
    if (needsDerivedLight(config_))
        derivedLight_ = dominantLight(environment);
    applyLight();
    renderer_->setEnvironmentSource(environmentSourceFor(config_.environment));
    placeScene(models);
}

void Pipeline::warmUp(const CameraIntrinsics& intrinsics)
{
    // Every marker and map 0.5 m ahead, its normal tilted 45 degrees towards the camera
    // (above the view's centre): the objects, their shadows and the phantoms in view.
    constexpr double kTilt = 0.7853981633974483;
    Pose view;
    view.R = glm::dmat3(glm::dvec3(1.0, 0.0, 0.0), glm::dvec3(0.0, -std::cos(kTilt), std::sin(kTilt)),
                        glm::dvec3(0.0, -std::sin(kTilt), -std::cos(kTilt)));
    view.t = glm::dvec3(0.0, 0.0, 0.5);
    const glm::dmat4 cameraFromMarker = view.matrix();
    drawItems_.clear();
    for (size_t i = 0; i < objects_.size(); ++i)
        drawItems_.push_back({objects_[i].model, cameraFromMarker * objects_[i].markerFromModel, int(i)});
    for (const PlacedObject& phantom : phantoms_)
        drawItems_.push_back({phantom.model, cameraFromMarker * phantom.markerFromModel, -1, true});
    for (const PlacedObject& ground : grounds_)
        drawItems_.push_back({ground.model, cameraFromMarker * ground.markerFromModel, -1, true, true});
    renderer_->setEnvironmentRotation(environmentFromMarker() * glm::transpose(view.R));
    Image8 grey(renderer_->width(), renderer_->height(), 3);
    std::fill(grey.data.begin(), grey.data.end(), uint8_t(128));
    renderer_->render(grey, intrinsics, drawItems_);
    renderer_->readback(grey);
    renderer_->forgetFrames();
    drawItems_.clear();
}

bool Pipeline::capturePacesItself() const
{
    const auto* prefetching = dynamic_cast<const PrefetchingSource*>(capture_.get());
    return prefetching && prefetching->mode() == PrefetchMode::LatestOnly;
}

uint64_t Pipeline::framesDropped() const
{
    const auto* prefetching = dynamic_cast<const PrefetchingSource*>(capture_.get());
    return prefetching ? prefetching->framesDropped() : 0;
}

void Pipeline::releaseLoadingMemory()
{
    // Loading frees tens of MB of transient buffers (decoded textures, file bytes, upload
    // copies) that glibc keeps in its heaps: freeing an mmapped block raises malloc's mmap
    // threshold, so later large blocks land on the heap and stay resident after free. Handing
    // the free pages back once here costs nothing per frame (issue 18: with the threshold held
    // fixed instead, the car scene's resident memory fell from 257 to 219–226 MB).
    (void)malloc_trim(0);
    (void)dropCleanFilePages();
}

void Pipeline::releaseStartupMemory()
{
    // The code start-up ran (loaders, the shader compilers) leaves the resident set; what the
    // frames run faults back on the next frame (issue 18: car.toml --replay, resident
    // 174 -> 104 MB, of which about 14 MB of hot code came back).
    const size_t dropped = dropCleanFilePages();
    LUMAR_LOG(App, Debug) << "start-up over: " << dropped / 1024 << " KiB of clean file pages dropped";
}

void Pipeline::applyLight()
{
    if (!config_.shadows.enabled)
        return;
    DirectionalLight light;
    const auto configured =
        std::find_if(config_.lights.begin(), config_.lights.end(), [](const LightConfig& l) { return l.shadow; });
    if (configured != config_.lights.end()) {
        light.direction = environmentFromMarker() * configured->direction;
        light.color = glm::vec3(configured->color);
        light.intensity = float(configured->intensity);
    } else if (config_.lights.empty() && derivedLight_) {
        light.direction = glm::dvec3(derivedLight_->direction);
        light.color = derivedLight_->color * float(config_.environment.intensity);
        light.intensity = 1.0f;
    } // else: lights are configured, none casting shadows: no light (contact darkening only)
    renderer_->setLight(light);
}

void Pipeline::placeScene(const std::vector<GltfModel>& models)
{
    objects_.clear();
    phantoms_.clear();
    for (size_t i = 0; i < models.size(); ++i) {
        const ObjectConfig& object = config_.objects[i];
        PlacedObject placed;
        placed.model = renderer_->addModel(models[i]);
        placed.marker = object.marker;
        for (size_t m = 0; m < config_.maps.size(); ++m)
            if (!object.map.empty() && config_.maps[m].name == object.map)
                placed.marker = TrackedPoses::mapKey(int(m));
        placed.markerFromModel = markerFromModel(object, models[i].boundsMin, models[i].boundsMax);
        placed.animation = resolveObjectAnimation(object, models[i]);
        objects_.push_back(placed);
        LUMAR_LOG(App, Info) << "object '" << object.name << "': " << object.model.string() << " ("
                             << models[i].triangleCount() << " triangles) on "
                             << (object.map.empty() ? "marker " + std::to_string(object.marker)
                                                    : "map '" + object.map + "'");
    }
    for (const PhantomConfig& phantom : config_.phantoms) {
        const PhantomModel shape = makePhantomModel(phantom);
        PlacedObject placed;
        placed.model = renderer_->addModel(shape.model);
        placed.marker = phantom.marker;
        placed.markerFromModel = shape.markerFromModel;
        phantoms_.push_back(placed);
    }
    placeGrounds(models);
    drawItems_.reserve(objects_.size() + phantoms_.size() + grounds_.size());
}

void Pipeline::placeGrounds(const std::vector<GltfModel>& models)
{
    grounds_.clear();
    if (!config_.shadows.enabled || !config_.shadows.ground || objects_.empty())
        return;
    std::map<int, std::vector<PlacedBox>> boxesByMarker;
    for (size_t i = 0; i < objects_.size(); ++i)
        boxesByMarker[objects_[i].marker].push_back(
            {objects_[i].markerFromModel, models[i].boundsMin, models[i].boundsMax});
    ModelId ground = -1;
    for (const auto& [marker, boxes] : boxesByMarker) {
        std::vector<PhantomConfig> phantoms;
        for (const PhantomConfig& phantom : config_.phantoms)
            if (phantom.marker == marker)
                phantoms.push_back(phantom);
        const std::optional<glm::dmat4> markerFromModel = groundUnder(boxes, phantoms);
        if (!markerFromModel)
            continue;
        if (ground < 0)
            ground = renderer_->addModel(makeGroundModel());
        grounds_.push_back({ground, marker, *markerFromModel, {}});
    }
}

Pipeline::PreparedReload Pipeline::prepareReload(const Config& next) const
{
    if (!keepsCamera(next))
        throw std::logic_error("Pipeline::prepareReload: the camera changed; that takes a new Pipeline");
    PreparedReload prepared;
    prepared.config = next;
    // The calibration file may have changed on disk under the same name: read it again.
    prepared.intrinsics = intrinsicsFor(next.camera, capture_->width(), capture_->height());
    const bool keepTracker = next.tracking == config_.tracking && next.markers == config_.markers &&
                             next.maps == config_.maps && sameIntrinsics(prepared.intrinsics, intrinsics_);
    if (!keepTracker)
        prepared.tracker = makeTracker(next, prepared.intrinsics);
    prepared.models = loadObjectModels(next);
    const bool keepRenderer = sameRendererSetup(config_, next);
    // The time is read before the file, so a write while it loads makes the next reload read it again.
    prepared.environmentWritten = environmentWritten(next.environment);
    if (!keepRenderer || next.environment != config_.environment ||
        prepared.environmentWritten != environmentWritten_ || (needsDerivedLight(next) && !derivedLight_)) {
        prepared.environment = loadEnvironment(next.environment);
        if (needsDerivedLight(next))
            prepared.environmentLight = dominantLight(*prepared.environment);
    }
    // Last: a new GL context only once every file has loaded.
    if (!keepRenderer)
        prepared.renderer = makeRenderer(next, capture_->width(), capture_->height(), profile_, window_);
    return prepared;
}

ReloadSummary Pipeline::applyReload(PreparedReload prepared)
{
    ReloadSummary summary;
    summary.keptTracker = !prepared.tracker;
    summary.keptRenderer = !prepared.renderer;
    summary.keptEnvironment = !prepared.environment;
    summary.modelsBefore = objects_.size();
    if (prepared.tracker) {
        // The detection thread uses the tracker being replaced: stop it first, start it again after.
        const bool background = worker_ != nullptr;
        worker_.reset();
        tracker_ = std::move(prepared.tracker);
        // Poses filtered with other settings, or maps under keys that now name other maps.
        tracked_ = TrackedPoses(prepared.config.tracking);
        latest_ = {};
        if (background)
            worker_ = std::make_unique<DetectionWorker>(*tracker_);
    }
    if (prepared.renderer) {
        renderer_ = std::move(prepared.renderer);
        displayLatencyMs_ = 0.0;
    } else {
        renderer_->removeModels();
    }
    if (prepared.config.output.overlay != config_.output.overlay)
        overlayOn_ = prepared.config.output.overlay;
    config_ = std::move(prepared.config);
    intrinsics_ = prepared.intrinsics;
    if (prepared.environment) {
        renderer_->setEnvironment(*prepared.environment, float(config_.environment.intensity));
        environmentWritten_ = prepared.environmentWritten;
        derivedLight_ = prepared.environmentLight;
    }
    applyLight();
    // A new configuration takes a new exposure reference; a map built from the camera holds
    // radiance relative to the old one, so it starts again too.
    exposureMeter_.reset();
    renderer_->setExposure(1.0f);
    renderer_->setEnvironmentSource(environmentSourceFor(config_.environment));
    placeScene(prepared.models);
    summary.modelsAfter = objects_.size();
    {
        const PreparedReload spent = std::move(prepared); // the loaded models and map, freed here
    }
    releaseLoadingMemory();
    return summary;
}

Pipeline::~Pipeline() = default;

bool Pipeline::step(FrameReport& report)
{
    auto start = std::chrono::steady_clock::now();
    if (!capture_->next(frame_))
        return false;
    report.sequence = frame_.sequence;
    report.timestampNs = frame_.timestampNs;
    report.capturedNs = frame_.capturedNs;
    report.times.captureMs = millisecondsSince(start);

    start = std::chrono::steady_clock::now();
    int64_t poseTimeNs = frame_.timestampNs;
    if (worker_) {
        // Never wait: hand the frame over and use the newest finished detection.
        worker_->submit(frame_.luma, frame_.sequence, frame_.timestampNs);
        if (worker_->take(latest_))
            tracked_.update(latest_.detections, latest_.maps, latest_.sequence, latest_.timestampNs);
        report.detections = latest_.detections;
        report.maps = latest_.maps;
        report.detectedSequence = latest_.sequence;
        report.times.detectMs = latest_.detectMs; // on the worker, not in this loop
        // The frame shows up about one render + readback after its capture.
        poseTimeNs += int64_t(displayLatencyMs_ * 1e6);
    } else {
        report.detections = tracker_->detect(frame_.luma);
        report.maps = tracker_->detectMaps(report.detections);
        tracked_.update(report.detections, report.maps, frame_.sequence, frame_.timestampNs);
        report.detectedSequence = frame_.sequence;
        report.times.detectMs = millisecondsSince(start);
    }

    start = std::chrono::steady_clock::now();
    // Every held marker's and map's pose for this frame, computed once: the objects are
    // placed with exactly these, and the report carries them.
    report.poseTimeNs = poseTimeNs;
    report.poses = tracked_.all(frame_.sequence, poseTimeNs);
    report.mapNames.clear();
    for (const MapConfig& map : config_.maps)
        report.mapNames.push_back(map.name);
    const auto poseOf = [&report](int key) -> const Pose* {
        for (const TrackedPoses::Used& used : report.poses)
            if (used.key == key)
                return &used.cameraFromMarker;
        return nullptr;
    };
    drawItems_.clear();
    report.objects.clear();
    const Pose* environmentAnchor = nullptr;
    const double seconds = sceneSeconds();
    for (size_t i = 0; i < objects_.size(); ++i) {
        const PlacedObject& object = objects_[i];
        const Pose* pose = poseOf(object.marker);
        if (!pose)
            continue;
        // Only objects in view are posed; one out of view resumes where its clock stands.
        if (object.animation.plays()) {
            clipTimesAt(object.animation, seconds, clips_);
            renderer_->poseModel(object.model, clips_);
        }
        // The configured object's index names its environment map from frame to frame.
        drawItems_.push_back({object.model, pose->matrix() * object.markerFromModel, int(i)});
        report.objects.push_back({int(i), object.marker, drawItems_.back().cameraFromModel});
        if (!environmentAnchor)
            environmentAnchor = pose;
    }
    for (const PlacedObject& phantom : phantoms_)
        if (const Pose* pose = poseOf(phantom.marker))
            drawItems_.push_back({phantom.model, pose->matrix() * phantom.markerFromModel, -1, true});
    const int objectsDrawn = int(drawItems_.size()); // objects and phantoms, not the grounds
    for (const PlacedObject& ground : grounds_)
        if (const Pose* pose = poseOf(ground.marker))
            drawItems_.push_back({ground.model, pose->matrix() * ground.markerFromModel, -1, true, true});
    if (environmentAnchor) {
        const glm::dmat3 markerFromCamera = glm::transpose(environmentAnchor->R);
        renderer_->setEnvironmentRotation(environmentFromMarker() * markerFromCamera);
    }
    if (config_.environment.matchExposure) {
        // The frame's objects follow the smoothed exposure (no flicker); the environment built
        // from the camera divides this image by its own, so a ramp leaves no trace in it.
        renderer_->setExposure(float(exposureMeter_.update(frame_.luma)));
        renderer_->setCameraImageExposure(float(exposureMeter_.frameExposure()));
    }
    // A source that kept the camera's YCbCr planes (v4l2 with camera.convert = "gpu") leaves
    // the conversion to the renderer; every other frame arrives as RGB.
    if (frame_.ycbcr.empty())
        renderer_->render(frame_.rgb, intrinsics_, drawItems_);
    else
        renderer_->render(frame_.ycbcr, intrinsics_, drawItems_);
    report.objectsDrawn = objectsDrawn;
    if (overlayOn_)
        drawSetupOverlay(report);
    report.times.renderMs = millisecondsSince(start);

    // On a display the frame goes to the screen without leaving the GPU; otherwise it is
    // read back for the headless sink.
    start = std::chrono::steady_clock::now();
    report.latencyMs.reset();
    if (window_) {
        renderer_->present(*window_);
        if (const auto shown = window_->presentedDuringLastSwap()) {
            const int64_t capturedNs = shown->swapsAgo == 0 ? frame_.capturedNs : previousCapturedNs_;
            if (capturedNs != 0 && shown->swapsAgo <= 1)
                report.latencyMs = double(shown->shownNs - capturedNs) * 1e-6;
        }
        previousCapturedNs_ = frame_.capturedNs;
    } else {
        renderer_->readback(output_);
        if (frame_.capturedNs != 0)
            report.latencyMs = double(monotonicClockNs() - frame_.capturedNs) * 1e-6;
    }
    report.times.readbackMs = millisecondsSince(start);
    if (framesRendered_ < kStartupFrames && ++framesRendered_ == kStartupFrames)
        releaseStartupMemory();
    const double latencyMs = report.times.renderMs + report.times.readbackMs;
    displayLatencyMs_ = displayLatencyMs_ > 0.0 ? 0.9 * displayLatencyMs_ + 0.1 * latencyMs : latencyMs;
    return true;
}

double Pipeline::sceneSeconds()
{
    if (!realTime_) {
        const double fps = capture_->fps();
        return fps > 0.0 ? double(frame_.sequence) / fps : 0.0;
    }
    if (!firstTimestampNs_)
        firstTimestampNs_ = frame_.timestampNs;
    return double(frame_.timestampNs - *firstTimestampNs_) * 1e-9;
}

void Pipeline::detectInBackground()
{
    if (!worker_)
        worker_ = std::make_unique<DetectionWorker>(*tracker_);
}

void Pipeline::drawSetupOverlay(const FrameReport& report)
{
    SetupOverlayInput input;
    input.intrinsics = intrinsics_;
    input.detections = report.detections;
    input.maps = report.maps;
    // The detections' windows: the worker's copy with background detection (the tracker is
    // the worker's then), the tracker's own otherwise.
    input.searchWindows = worker_ ? latest_.windows : tracker_->searchedWindows();
    input.tagSize = [this](int id) { return config_.markerSize(id); };
    input.mapAxisLength = [this](int index) {
        double largest = 0.0;
        if (index >= 0 && size_t(index) < config_.maps.size())
            for (const MapTagConfig& tag : config_.maps[size_t(index)].tags)
                largest = std::max(largest, tag.size);
        return largest;
    };
    input.status = "frame " + std::to_string(frame_.sequence) + "  markers " +
                   std::to_string(report.detections.size()) + "  objects " + std::to_string(report.objectsDrawn) +
                   (overlayStatus_.empty() ? "" : "  " + overlayStatus_);
    buildSetupOverlay(input, overlay_);
    renderer_->drawOverlay(overlay_);
}

RenderStats Pipeline::renderStats() const
{
    return renderer_->lastStats();
}

} // namespace lumar
