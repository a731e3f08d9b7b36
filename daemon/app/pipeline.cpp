#include "pipeline.h"

#include <chrono>

#include <glm/gtc/matrix_transform.hpp>

#include "capture/prefetching_source.h"
#include "core/error.h"
#include "core/log.h"
#include "gles_renderer/builtin_shapes.h"
#include "gles_renderer/environment_map.h"
#include "gles_renderer/gl_probe.h"
#include "gles_renderer/gltf_model.h"
#include "gles_renderer/material_sidecar.h"
#include "object_placement.h"
#include "tracking/calibration_io.h"

namespace lumar {
namespace {

// A marker missed for a few frames (motion blur, a hand passing) keeps its last pose so
// objects do not flicker; after that they disappear rather than float in a stale place.
constexpr uint64_t kMarkerHoldFrames = 5;

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

// The object's model with its materials: a file or a built-in shape, then the sidecar's
// Lafortune materials, then the preset for every material.
GltfModel loadObjectModel(const ObjectConfig& object)
{
    const std::string model = object.model.string();
    GltfModel loaded = model.starts_with(kBuiltinModelPrefix)
                           ? makeBuiltinShape(std::string_view(model).substr(kBuiltinModelPrefix.size()))
                           : loadGltfModel(object.model);
    if (!object.materials.empty())
        applyMaterialSidecar(loaded, loadMaterialSidecar(object.materials));
    if (!object.material.empty()) {
        MaterialSidecar everything;
        everything.materials["*"].preset = object.material;
        applyMaterialSidecar(loaded, everything);
    }
    return loaded;
}

RenderOptions renderOptionsFor(const RenderingConfig& rendering)
{
    RenderOptions options;
    EnvironmentMapOptions& maps = options.environmentMaps;
    maps.dynamic = rendering.environmentMaps != "off";
    maps.policy = rendering.environmentMaps == "every_k"     ? EnvironmentMapPolicy::EveryKFrames
                  : rendering.environmentMaps == "budget"    ? EnvironmentMapPolicy::Budget
                  : rendering.environmentMaps == "on_change" ? EnvironmentMapPolicy::OnChange
                                                             : EnvironmentMapPolicy::EveryFrame;
    maps.everyK = rendering.environmentMapEvery;
    maps.budgetMs = rendering.environmentMapBudgetMs;
    maps.ibl.mirrorSize = rendering.environmentMapSize;
    return options;
}

// camera.convert = "auto": YCbCr to RGB on the GPU unless the GLES implementation is a
// software rasteriser, where the full-screen conversion pass costs more (measured on
// llvmpipe, 2 cores: 30 -> 25 fps) than the CPU conversion it saves.
CameraConfig withConversionDecided(CameraConfig camera)
{
    if (camera.convert != "auto" || camera.source != "v4l2")
        return camera;
    std::string renderer;
    try {
        renderer = probeGl().glRenderer;
    } catch (const RuntimeError&) {
        // No EGL: the renderer will say so when it is created.
    }
    const bool software = renderer.find("llvmpipe") != std::string::npos ||
                          renderer.find("softpipe") != std::string::npos ||
                          renderer.find("swrast") != std::string::npos;
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

} // namespace

Pipeline::Pipeline(const Config& config, bool profile) : config_(config)
{
    filterSettings_.minCutoffHz = config_.tracking.filterMinCutoffHz;
    filterSettings_.beta = config_.tracking.filterBeta;
    filterSettings_.rotationMinCutoffHz = config_.tracking.filterRotationMinCutoffHz;
    filterSettings_.rotationBeta = config_.tracking.filterRotationBeta;
    capture_ = std::make_unique<PrefetchingSource>(openCaptureSource(withConversionDecided(config_.camera)));
    intrinsics_ = intrinsicsFor(config_.camera, capture_->width(), capture_->height());
    tracker_ = std::make_unique<TagTracker>(config_.tracking, intrinsics_, tagSizesFor(config_));
    std::vector<TagMap> maps;
    for (const MapConfig& map : config_.maps)
        maps.push_back(makeTagMap(map));
    tracker_->setMaps(std::move(maps));

    // Load every file before creating the GL context, so bad input is reported as such even
    // on a machine without EGL.
    std::vector<GltfModel> models;
    models.reserve(config_.objects.size());
    for (const ObjectConfig& object : config_.objects)
        models.push_back(loadObjectModel(object));
    const ImageF environment =
        config_.environment.hdr.empty() ? neutralEnvironment() : loadHdrImage(config_.environment.hdr);

    RenderOptions options = renderOptionsFor(config_.rendering);
    options.profile = profile;
    renderer_ = SceneRenderer::create(capture_->width(), capture_->height(), options);
    renderer_->setEnvironment(environment, float(config_.environment.intensity));
    for (size_t i = 0; i < models.size(); ++i) {
        const ObjectConfig& object = config_.objects[i];
        PlacedObject placed;
        placed.model = renderer_->addModel(models[i]);
        placed.marker = object.marker;
        for (size_t m = 0; m < config_.maps.size(); ++m)
            if (!object.map.empty() && config_.maps[m].name == object.map)
                placed.marker = mapKey(int(m));
        placed.markerFromModel = markerFromModel(object, models[i].boundsMin, models[i].boundsMax);
        objects_.push_back(placed);
        LUMAR_LOG(App, Info) << "object '" << object.name << "': " << object.model.string() << " ("
                             << models[i].triangleCount() << " triangles) on "
                             << (object.map.empty() ? "marker " + std::to_string(object.marker)
                                                    : "map '" + object.map + "'");
    }
    for (const PhantomConfig& phantom : config_.phantoms) {
        GltfModel box = makeCube();
        GltfMaterial& material = box.materials[0];
        material.name = phantom.name;
        material.baseColorFactor = glm::vec4(glm::vec3(phantom.color), 1.0f);
        material.metallicFactor = 0.0f;
        material.roughnessFactor = 1.0f;
        PlacedObject placed;
        placed.model = renderer_->addModel(box);
        placed.marker = phantom.marker;
        placed.markerFromModel =
            glm::translate(glm::dmat4(1.0), phantom.offset) * glm::scale(glm::dmat4(1.0), phantom.size);
        phantoms_.push_back(placed);
    }
    drawItems_.reserve(objects_.size() + phantoms_.size());
}

Pipeline::~Pipeline() = default;

void Pipeline::updateMarkers(const std::vector<TagDetection>& detections, uint64_t sequence, int64_t timestampNs)
{
    for (const TagDetection& d : detections) {
        if (!d.hasPose)
            continue;
        auto [it, inserted] = markers_.try_emplace(d.id);
        MarkerState& marker = it->second;
        if (inserted)
            marker.filter = OneEuroPoseFilter(filterSettings_);
        marker.cameraFromMarker =
            config_.tracking.filter ? marker.filter.update(d.cameraFromMarker, timestampNs) : d.cameraFromMarker;
        marker.lastSeen = sequence;
    }
}

void Pipeline::updateMaps(const std::vector<MapDetection>& maps, uint64_t sequence, int64_t timestampNs)
{
    for (const MapDetection& map : maps) {
        auto [it, inserted] = markers_.try_emplace(mapKey(map.index));
        MarkerState& state = it->second;
        if (inserted)
            state.filter = OneEuroPoseFilter(filterSettings_);
        state.cameraFromMarker =
            config_.tracking.filter ? state.filter.update(map.cameraFromMap, timestampNs) : map.cameraFromMap;
        state.lastSeen = sequence;
    }
}

bool Pipeline::step(FrameReport& report)
{
    auto start = std::chrono::steady_clock::now();
    if (!capture_->next(frame_))
        return false;
    report.sequence = frame_.sequence;
    report.timestampNs = frame_.timestampNs;
    report.times.captureMs = millisecondsSince(start);

    start = std::chrono::steady_clock::now();
    int64_t poseTimeNs = frame_.timestampNs;
    if (worker_) {
        // Never wait: hand the frame over and use the newest finished detection.
        worker_->submit(frame_.luma, frame_.sequence, frame_.timestampNs);
        if (worker_->take(latest_)) {
            updateMarkers(latest_.detections, latest_.sequence, latest_.timestampNs);
            updateMaps(latest_.maps, latest_.sequence, latest_.timestampNs);
        }
        report.detections = latest_.detections;
        report.maps = latest_.maps;
        report.times.detectMs = latest_.detectMs; // on the worker, not in this loop
        // The frame shows up about one render + readback after its capture.
        poseTimeNs += int64_t(displayLatencyMs_ * 1e6);
    } else {
        report.detections = tracker_->detect(frame_.luma);
        updateMarkers(report.detections, frame_.sequence, frame_.timestampNs);
        report.maps = tracker_->detectMaps(report.detections);
        updateMaps(report.maps, frame_.sequence, frame_.timestampNs);
        report.times.detectMs = millisecondsSince(start);
    }

    start = std::chrono::steady_clock::now();
    drawItems_.clear();
    const MarkerState* environmentAnchor = nullptr;
    for (size_t i = 0; i < objects_.size(); ++i) {
        const PlacedObject& object = objects_[i];
        const auto it = markers_.find(object.marker);
        if (it == markers_.end() || frame_.sequence - it->second.lastSeen > kMarkerHoldFrames)
            continue;
        // The configured object's index names its environment map from frame to frame.
        drawItems_.push_back({object.model, poseAt(it->second, poseTimeNs).matrix() * object.markerFromModel, int(i)});
        if (!environmentAnchor)
            environmentAnchor = &it->second;
    }
    for (const PlacedObject& phantom : phantoms_) {
        const auto it = markers_.find(phantom.marker);
        if (it != markers_.end() && frame_.sequence - it->second.lastSeen <= kMarkerHoldFrames)
            drawItems_.push_back(
                {phantom.model, poseAt(it->second, poseTimeNs).matrix() * phantom.markerFromModel, -1, true});
    }
    if (environmentAnchor) {
        const glm::dmat3 markerFromCamera = glm::transpose(poseAt(*environmentAnchor, poseTimeNs).R);
        renderer_->setEnvironmentRotation(environmentFromMarker() * markerFromCamera);
    }
    // A source that kept the camera's YCbCr planes (v4l2 with camera.convert = "gpu") leaves
    // the conversion to the renderer; every other frame arrives as RGB.
    if (frame_.ycbcr.empty())
        renderer_->render(frame_.rgb, intrinsics_, drawItems_);
    else
        renderer_->render(frame_.ycbcr, intrinsics_, drawItems_);
    report.objectsDrawn = int(drawItems_.size());
    report.times.renderMs = millisecondsSince(start);

    start = std::chrono::steady_clock::now();
    renderer_->readback(output_);
    report.times.readbackMs = millisecondsSince(start);
    const double latencyMs = report.times.renderMs + report.times.readbackMs;
    displayLatencyMs_ = displayLatencyMs_ > 0.0 ? 0.9 * displayLatencyMs_ + 0.1 * latencyMs : latencyMs;
    return true;
}

void Pipeline::detectInBackground()
{
    if (!worker_)
        worker_ = std::make_unique<DetectionWorker>(*tracker_);
}

Pose Pipeline::poseAt(const MarkerState& marker, int64_t timestampNs) const
{
    // The filter extrapolates with its velocities; unfiltered poses stay as measured.
    return config_.tracking.filter && marker.filter.initialised() ? marker.filter.predict(timestampNs)
                                                                  : marker.cameraFromMarker;
}

RenderStats Pipeline::renderStats() const
{
    return renderer_->lastStats();
}

} // namespace lumar
