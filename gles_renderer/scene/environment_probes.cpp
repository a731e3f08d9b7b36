#include "gles_renderer/scene/environment_probes.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include <glm/gtc/matrix_transform.hpp>

#include "gles_renderer/gl/gl_check.h"
#include "gles_renderer/ibl/cube_face_camera.h"
#include "gles_renderer/scene/camera_projection.h"
#include "gles_renderer/scene/stage_timer.h"

namespace lumar {
namespace {

// Faces see neighbours a few centimetres away; the owner is hidden, so nothing is closer.
constexpr double kFaceNearMetres = 0.002;

glm::dvec3 boundsCentre(const GpuModel& model)
{
    return 0.5 * (glm::dvec3(model.boundsMin) + glm::dvec3(model.boundsMax));
}

// Whether the bounding sphere of `item` (in a face camera's frame) reaches into the face's
// frustum: in front of the camera and inside the four planes |x| = z, |y| = z (90 degrees).
bool mayBeInFace(const DrawItem& item, const GpuModel& model)
{
    const glm::dvec3 centre = glm::dvec3(item.cameraFromModel * glm::dvec4(boundsCentre(model), 1.0));
    const glm::dmat3 linear(item.cameraFromModel);
    const double scale = std::max({glm::length(linear[0]), glm::length(linear[1]), glm::length(linear[2])});
    const double radius = scale * 0.5 * glm::length(glm::dvec3(model.boundsMax) - glm::dvec3(model.boundsMin));
    const double slack = radius * std::numbers::sqrt2; // distance to a 45-degree plane
    return centre.z > -radius && std::abs(centre.x) <= centre.z + slack && std::abs(centre.y) <= centre.z + slack;
}

// OnChange: updates after a change, one bounce of inter-reflection each; three bring a pair
// of mirrors within a few percent of their steady state.
constexpr int kSettlingUpdates = 3;
// Scene changes below these are tracking noise (a filtered still marker moves < 0.1 degree).
constexpr double kSceneTranslationToleranceMetres = 0.002;
constexpr double kSceneLinearTolerance = 0.003;

// Every item's model in the environment frame, translations relative to the first item's:
// the maps (centred on their objects, axes along the environment) depend on nothing else.
void describeScene(std::span<const DrawItem> items, const EnvironmentLighting& environment,
                   std::vector<glm::dmat4>& scene)
{
    scene.clear();
    const glm::dmat4 environmentFromCamera(environment.environmentFromCamera());
    for (const DrawItem& item : items)
        scene.push_back(environmentFromCamera * item.cameraFromModel);
    if (scene.empty())
        return;
    const glm::dvec4 origin = scene.front()[3];
    for (glm::dmat4& m : scene)
        m[3] = glm::dvec4(glm::dvec3(m[3] - origin), 1.0);
}

// Whether pose `b` is within `linearTolerance` (relative, per column of the linear part) and
// `metres` (translation) of pose `a`.
bool posesClose(const glm::dmat4& a, const glm::dmat4& b, double linearTolerance, double metres)
{
    for (int c = 0; c < 3; ++c)
        if (glm::length(glm::dvec3(a[c] - b[c])) > linearTolerance * glm::length(glm::dvec3(a[c])))
            return false;
    return glm::length(glm::dvec3(a[3] - b[3])) <= metres;
}

bool sameScene(const std::vector<glm::dmat4>& a, const std::vector<glm::dmat4>& b)
{
    if (a.size() != b.size())
        return false;
    for (size_t i = 0; i < a.size(); ++i)
        if (!posesClose(a[i], b[i], kSceneLinearTolerance, kSceneTranslationToleranceMetres))
            return false;
    return true;
}

// Phantom layers are reused while every phantom stays within this of where the layer shows
// it: floating-point noise of poses composed from the same marker, far below a texel.
constexpr double kLayerToleranceMetres = 1e-6;
constexpr double kLayerLinearTolerance = 1e-6;

bool samePhantoms(const std::vector<std::pair<int, glm::dmat4>>& a, const std::vector<std::pair<int, glm::dmat4>>& b)
{
    if (a.size() != b.size())
        return false;
    for (size_t i = 0; i < a.size(); ++i)
        if (a[i].first != b[i].first ||
            !posesClose(a[i].second, b[i].second, kLayerLinearTolerance, kLayerToleranceMetres))
            return false;
    return true;
}

} // namespace

EnvironmentProbes::EnvironmentProbes(const EnvironmentMapOptions& options)
    : options_(options), pipeline_(options.ibl), environmentMaps_(pipeline_.createMaps())
{
}

const IblMaps* EnvironmentProbes::objectMaps(int object) const
{
    const auto it = probes_.find(object);
    return it != probes_.end() && it->second.ready ? &it->second : nullptr;
}

void EnvironmentProbes::rebuildEnvironmentMaps(const EnvironmentLighting& environment)
{
    pipeline_.renderMirror(environmentMaps_, nullptr, [&](int face) {
        pipeline_.drawSkybox(face, environment.equirect(), environment.equirectWidth(), 1.0f);
    });
    pipeline_.updateDerivedMaps(environmentMaps_);
    environmentGeneration_ = environment.generation();
    // Every object's maps show the old environment: render them again before use.
    probes_.clear();
    history_.clear();
    phantomLayers_.clear();
    checkGlError("building the real environment's maps");
}

void EnvironmentProbes::refreshEnvironmentMaps(const EnvironmentLighting& environment,
                                               const std::function<void(int face)>& drawSkybox)
{
    pipeline_.renderMirror(environmentMaps_, nullptr, drawSkybox);
    pipeline_.updateDerivedMaps(environmentMaps_);
    environmentGeneration_ = environment.generation();
    for (auto& [object, history] : history_)
        history.bouncesLeft = kSettlingUpdates;
    // The phantoms are lit by the real environment's maps: their layers are drawn again.
    for (auto& [object, layer] : phantomLayers_)
        layer.drawn = false;
    checkGlError("refreshing the real environment's maps");
}

void EnvironmentProbes::chooseUpdates(const std::vector<GpuModel>& models, std::span<const DrawItem> items,
                                      const EnvironmentLighting& environment)
{
    updates_.clear();
    // Animated models change shape where they stand: each pose counts as a change.
    uint64_t poses = 0;
    if (options_.policy == EnvironmentMapPolicy::OnChange) {
        describeScene(items, environment, scene_);
        for (const DrawItem& item : items)
            poses += models[size_t(item.model)].poseGeneration;
    }
    std::vector<size_t>& owners = owners_; // items with a dynamic map, in order
    owners.clear();
    for (size_t i = 0; i < items.size(); ++i)
        if (items[i].object >= 0 && !items[i].phantom)
            owners.push_back(i);
    if (owners.empty())
        return;
    for (size_t k = 0; k < owners.size(); ++k) {
        const size_t i = owners[k];
        const bool ready = objectMaps(items[i].object) != nullptr;
        switch (options_.policy) {
        case EnvironmentMapPolicy::EveryFrame:
            updates_.push_back(i);
            break;
        case EnvironmentMapPolicy::EveryKFrames:
            // Staggered: object k updates on frames where (frame + k) % everyK == 0.
            if (!ready || (frame_ + long(k)) % std::max(1, options_.everyK) == 0)
                updates_.push_back(i);
            break;
        case EnvironmentMapPolicy::Budget:
            break;
        case EnvironmentMapPolicy::OnChange: {
            History& history = history_[items[i].object];
            if (!ready || !sameScene(history.scene, scene_) || history.poses != poses) {
                history.scene = scene_;
                history.poses = poses;
                history.bouncesLeft = kSettlingUpdates;
            }
            if (history.bouncesLeft > 0) {
                updates_.push_back(i);
                --history.bouncesLeft;
            }
            break;
        }
        }
    }
    if (options_.policy != EnvironmentMapPolicy::Budget)
        return;
    // Round-robin from where the last frame stopped, while the estimate fits the budget.
    const size_t count = owners.size();
    const size_t affordable = probeCostMs_ > 0.0 ? size_t(std::max(1.0, options_.budgetMs / probeCostMs_)) : size_t(1);
    for (size_t n = 0; n < std::min(count, affordable); ++n)
        updates_.push_back(owners[(roundRobin_ + n) % count]);
    roundRobin_ = (roundRobin_ + std::min(count, affordable)) % count;
}

void EnvironmentProbes::renderProbe(size_t owner, const std::vector<GpuModel>& models, std::span<const DrawItem> items,
                                    const EnvironmentLighting& environment, const MeshPass& meshes,
                                    const ShadowPass& shadows, const CameraView& camera, RenderCpuClock* cpu,
                                    bool finish, RenderStats& stats)
{
    IblMaps& maps = probes_[items[owner].object];
    if (!maps.mirror)
        maps = pipeline_.createMaps();

    const glm::dmat4& ownerFromModel = items[owner].cameraFromModel;
    const glm::dvec3 centre =
        glm::dvec3(ownerFromModel * glm::dvec4(boundsCentre(models[size_t(items[owner].model)]), 1.0));
    const int size = pipeline_.settings().mirrorSize;
    const glm::dmat4 clip = clipFromCamera(faceIntrinsics(size), size, size, kFaceNearMetres);

    // Phantoms carry the camera image (phantom.frag) when the frame has one and the phantoms'
    // depth as the camera saw them.
    const bool cameraPhantoms = camera.texture != 0 && camera.phantomDepth != 0;
    MeshPass::PhantomCamera phantomCamera;
    phantomCamera.clipFromFrameCamera = camera.clipFromCamera;
    phantomCamera.exposure = camera.exposure;
    phantomCamera.image = camera.texture;
    phantomCamera.depth = camera.phantomDepth;

    // Draws the items (all but the owner, or the phantoms alone) into face `face`, the
    // phantoms shaded or into depth alone (MeshPass::Phantoms).
    const auto drawFace = [&](int face, bool phantomsOnly, MeshPass::Phantoms phantoms) {
        const glm::dmat3 faceFromCube = faceCameraFromCube(face);
        const glm::dmat4 faceFromCamera =
            glm::dmat4(faceFromCube * environment.environmentFromCamera()) * glm::translate(glm::dmat4(1.0), -centre);
        phantomCamera.frameCameraFromView = glm::mat4(glm::inverse(faceFromCamera));
        // Only what the face's 90-degree frustum can see: each neighbour usually shows in
        // one or two faces of six.
        faceItems_.clear();
        faceMaps_.clear();
        for (size_t i = 0; i < items.size(); ++i) {
            if (i == owner || (phantomsOnly && !items[i].phantom))
                continue;
            DrawItem item = items[i];
            item.cameraFromModel = faceFromCamera * item.cameraFromModel;
            if (!mayBeInFace(item, models[size_t(item.model)])) {
                ++stats.facesCulled;
                continue;
            }
            faceItems_.push_back(item);
            faceMaps_.push_back(maps_[i]);
        }
        FrameUniforms frame;
        frame.clipFromCamera = glm::mat4(clip);
        const glm::mat3 environmentFromFace(glm::transpose(faceFromCube));
        for (int c = 0; c < 3; ++c)
            frame.environmentFromCamera[c] = glm::vec4(environmentFromFace[c], 0.0f);
        // Mirrored frame, linear radiance (RGBM-encoded where the maps are RGBA8).
        frame.frameParams = glm::vec4(-1.0f, 1.0f, pipeline_.rgbm() ? 1.0f : 0.0f, 1.0f);
        shadows.fillView(frame, glm::inverse(faceFromCamera));
        meshes.draw(frame, models, faceItems_, faceMaps_, -1, phantoms, MeshPass::Detail::Proxy,
                    faceIntrinsics(size).fx, cameraPhantoms ? &phantomCamera : nullptr);
    };

    StageTimer timer(cpu, finish);
    // The phantoms as the layer would show them now, in the environment frame about the centre.
    phantomScene_.clear();
    const glm::dmat4 environmentFromCentre =
        glm::dmat4(environment.environmentFromCamera()) * glm::translate(glm::dmat4(1.0), -centre);
    for (const DrawItem& item : items)
        if (item.phantom)
            phantomScene_.emplace_back(item.model, environmentFromCentre * item.cameraFromModel);
    const IblMaps* backdrop = &environmentMaps_;
    if (cameraPhantoms) // the camera image changes every frame: a layer would be stale at once
        phantomLayers_.erase(items[owner].object);
    else if (!phantomScene_.empty()) {
        PhantomLayer& layer = phantomLayers_[items[owner].object];
        if (!samePhantoms(layer.phantoms, phantomScene_)) {
            layer.phantoms = phantomScene_;
            layer.drawn = false;
        } else {
            if (!layer.drawn) {
                if (!layer.maps.mirror)
                    layer.maps = pipeline_.createMaps();
                pipeline_.renderMirror(layer.maps, &environmentMaps_,
                                       [&](int face) { drawFace(face, true, MeshPass::Phantoms::Shaded); });
                layer.drawn = true;
            }
            backdrop = &layer.maps;
        }
    }
    const MeshPass::Phantoms phantoms =
        backdrop == &environmentMaps_ ? MeshPass::Phantoms::Shaded : MeshPass::Phantoms::DepthOnly;
    pipeline_.renderMirror(maps, backdrop, [&](int face) { drawFace(face, false, phantoms); });
    timer.split(stats.environmentMaps);
    pipeline_.projectSH(maps);
    timer.split(stats.sh);
    pipeline_.prefilter(maps);
    timer.split(stats.prefilter);
    ++stats.mapsUpdated;
}

std::span<const IblMaps* const>
EnvironmentProbes::update(const std::vector<GpuModel>& models, std::span<const DrawItem> items,
                          const EnvironmentLighting& environment, const MeshPass& meshes, const ShadowPass& shadows,
                          const CameraView& camera, RenderCpuClock* profile, RenderStats& stats)
{
    if (environment.generation() != environmentGeneration_)
        rebuildEnvironmentMaps(environment);

    maps_.resize(items.size());
    for (size_t i = 0; i < items.size(); ++i) {
        const IblMaps* own =
            options_.dynamic && items[i].object >= 0 && !items[i].phantom ? objectMaps(items[i].object) : nullptr;
        maps_[i] = own ? own : &environmentMaps_;
    }
    if (options_.dynamic) {
        chooseUpdates(models, items, environment);
        const bool timeProbes = options_.policy == EnvironmentMapPolicy::Budget;
        for (const size_t i : updates_) {
            const double before = stats.environmentMaps.wallMs + stats.sh.wallMs + stats.prefilter.wallMs;
            renderProbe(i, models, items, environment, meshes, shadows, camera, profile,
                        profile != nullptr || timeProbes, stats);
            if (timeProbes) {
                const double cost = stats.environmentMaps.wallMs + stats.sh.wallMs + stats.prefilter.wallMs - before;
                probeCostMs_ = probeCostMs_ > 0.0 ? 0.8 * probeCostMs_ + 0.2 * cost : cost;
            }
            // From now on this frame (later probes and the frame itself) sees the new maps.
            maps_[i] = &probes_[items[i].object];
        }
    }
    ++frame_;
    return maps_;
}

} // namespace lumar
