#include "gles_renderer/scene/environment_probes.h"

#include <algorithm>
#include <cmath>
#include <utility>

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

// Whether `item`'s bounding box (its model's, in a face camera's frame) may reach into the
// face's frustum: in front of the camera and inside the four planes |x| = z, |y| = z (90
// degrees). The box lies outside where all eight corners are on the outer side of one plane;
// a box the planes cut (or one round the camera) is kept. Tighter than a bounding sphere
// for the long, flat models neighbours are: in the car scene the roadster's sphere reached
// into three faces of each neighbour's map where its box reaches one, and every face it is
// drawn into costs all its stand-in's vertices (12,000 of the 31,000 triangles a frame).
bool mayBeInFace(const DrawItem& item, const GpuModel& model)
{
    // Per plane, whether every corner so far lies on its outer side.
    bool behind = true, right = true, left = true, above = true, below = true;
    for (const glm::dvec3& p : boundsCorners(model, item.cameraFromModel)) {
        behind = behind && p.z <= 0.0;
        right = right && p.x > p.z;
        left = left && -p.x > p.z;
        above = above && p.y > p.z;
        below = below && -p.y > p.z;
    }
    return !(behind || right || left || above || below);
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

FrameUniforms cubeFaceFrameUniforms(int face, int size, bool rgbm)
{
    FrameUniforms frame;
    frame.clipFromCamera = glm::mat4(clipFromCamera(faceIntrinsics(size), size, size, kFaceNearMetres));
    const glm::mat3 environmentFromFace(glm::transpose(faceCameraFromCube(face)));
    for (int c = 0; c < 3; ++c)
        frame.environmentFromCamera[c] = glm::vec4(environmentFromFace[c], 0.0f);
    frame.frameParams = glm::vec4(-1.0f, 1.0f, rgbm ? 1.0f : 0.0f, 1.0f);
    return frame;
}

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
    clear();
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

bool EnvironmentProbes::hasSlot(int object) const
{
    for (const Bank& bank : banks_)
        if (std::find(bank.objects.begin(), bank.objects.end(), object) != bank.objects.end())
            return true;
    return false;
}

std::pair<size_t, int> EnvironmentProbes::slotOf(int object, int wanted)
{
    for (size_t b = 0; b < banks_.size(); ++b)
        for (size_t k = 0; k < banks_[b].objects.size(); ++k)
            if (banks_[b].objects[k] == object)
                return {b, int(k)};
    for (size_t b = 0; b < banks_.size(); ++b)
        for (size_t k = 0; k < banks_[b].objects.size(); ++k)
            if (banks_[b].objects[k] < 0) {
                banks_[b].objects[k] = object;
                return {b, int(k)};
            }
    Bank bank;
    const int slots = pipeline_.maxBankSlots(std::clamp(wanted, 1, kBankSlots));
    bank.maps = pipeline_.createMaps(slots);
    bank.previousMirror = pipeline_.createMirror(slots);
    bank.objects.assign(size_t(slots), -1);
    bank.objects[0] = object;
    banks_.push_back(std::move(bank));
    return {banks_.size() - 1, 0};
}

void EnvironmentProbes::drawProbeFace(const Probe& probe, int face, bool phantomsOnly, MeshPass::Phantoms phantoms,
                                      const std::vector<GpuModel>& models, std::span<const DrawItem> items,
                                      const EnvironmentLighting& environment, const MeshPass& meshes,
                                      const ShadowPass& shadows, const CameraView& camera, RenderStats& stats)
{
    const int size = pipeline_.settings().mirrorSize;
    // Phantoms carry the camera image (phantom.frag) when the frame has one and the phantoms'
    // depth as the camera saw them.
    const bool cameraPhantoms = camera.texture != 0 && camera.phantomDepth != 0;
    MeshPass::PhantomCamera phantomCamera;
    phantomCamera.clipFromFrameCamera = camera.clipFromCamera;
    phantomCamera.exposure = camera.exposure;
    phantomCamera.image = camera.texture;
    phantomCamera.depth = camera.phantomDepth;

    const glm::dmat3 faceFromCube = faceCameraFromCube(face);
    const glm::dmat4 faceFromCamera =
        glm::dmat4(faceFromCube * environment.environmentFromCamera()) * glm::translate(glm::dmat4(1.0), -probe.centre);
    phantomCamera.frameCameraFromView = glm::mat4(glm::inverse(faceFromCamera));
    // Only what the face's 90-degree frustum can see: each neighbour usually shows in
    // one or two faces of six.
    faceItems_.clear();
    faceMaps_.clear();
    for (size_t i = 0; i < items.size(); ++i) {
        if (i == probe.owner || (phantomsOnly && !items[i].phantom))
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
    FrameUniforms frame = cubeFaceFrameUniforms(face, size, pipeline_.rgbm());
    shadows.fillView(frame, glm::inverse(faceFromCamera));
    meshes.draw(frame, models, faceItems_, faceMaps_, -1, phantoms, MeshPass::Detail::Proxy, faceIntrinsics(size).fx,
                cameraPhantoms ? &phantomCamera : nullptr);
}

EnvironmentProbes::Probe EnvironmentProbes::prepareProbe(size_t owner, const std::vector<GpuModel>& models,
                                                         std::span<const DrawItem> items,
                                                         const EnvironmentLighting& environment, const MeshPass& meshes,
                                                         const ShadowPass& shadows, const CameraView& camera,
                                                         RenderStats& stats)
{
    Probe probe;
    probe.owner = owner;
    const glm::dmat4& ownerFromModel = items[owner].cameraFromModel;
    probe.centre = glm::dvec3(ownerFromModel * glm::dvec4(boundsCentre(models[size_t(items[owner].model)]), 1.0));
    const bool cameraPhantoms = camera.texture != 0 && camera.phantomDepth != 0;

    // The phantoms as the layer would show them now, in the environment frame about the centre.
    phantomScene_.clear();
    const glm::dmat4 environmentFromCentre =
        glm::dmat4(environment.environmentFromCamera()) * glm::translate(glm::dmat4(1.0), -probe.centre);
    for (const DrawItem& item : items)
        if (item.phantom)
            phantomScene_.emplace_back(item.model, environmentFromCentre * item.cameraFromModel);
    probe.backdrop = &environmentMaps_;
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
                pipeline_.renderMirror(layer.maps, &environmentMaps_, [&](int face) {
                    drawProbeFace(probe, face, true, MeshPass::Phantoms::Shaded, models, items, environment, meshes,
                                  shadows, camera, stats);
                });
                layer.drawn = true;
            }
            probe.backdrop = &layer.maps;
        }
    }
    probe.phantoms = probe.backdrop == &environmentMaps_ ? MeshPass::Phantoms::Shaded : MeshPass::Phantoms::DepthOnly;
    return probe;
}

void EnvironmentProbes::renderBank(size_t b, std::span<const size_t> updates, const std::vector<GpuModel>& models,
                                   std::span<const DrawItem> items, const EnvironmentLighting& environment,
                                   const MeshPass& meshes, const ShadowPass& shadows, const CameraView& camera,
                                   RenderCpuClock* cpu, bool finish, RenderStats& stats)
{
    StageTimer timer(cpu, finish);
    probesThisPass_.clear();
    for (const size_t i : updates)
        probesThisPass_.push_back(prepareProbe(i, models, items, environment, meshes, shadows, camera, stats));

    Bank& bank = banks_[b];
    // What the faces see of this bank's objects is the last pass's maps: the texture drawn
    // now is never read while it is drawn.
    std::swap(bank.maps.mirror, bank.previousMirror);
    const auto pointViews = [&](GLuint mirror) {
        for (size_t k = 0; k < bank.objects.size(); ++k)
            if (bank.objects[k] >= 0) {
                IblMaps& view = probes_[bank.objects[k]];
                view.view = {mirror,
                             bank.maps.coefficients.name(),
                             bank.maps.diffuse.name(),
                             bank.maps.glossy1.name(),
                             bank.maps.glossy2.name(),
                             int(k),
                             bank.maps.slots};
                view.mirrorLevels = bank.maps.mirrorLevels;
            }
    };
    pointViews(bank.previousMirror.name());

    mirrorSlots_.clear();
    updatedSlots_.clear();
    // The derived maps only of the slots whose objects read them (EnvironmentMapReads).
    shSlots_.clear();
    glossySlots_.clear();
    glossy1Slots_.clear();
    for (size_t k = 0; k < bank.objects.size(); ++k) {
        const int object = bank.objects[k];
        if (object < 0)
            continue;
        const auto probe = std::find_if(probesThisPass_.begin(), probesThisPass_.end(),
                                        [&](const Probe& p) { return items[p.owner].object == object; });
        IblPipeline::MirrorSlot slot;
        slot.slot = int(k);
        if (probe != probesThisPass_.end()) {
            slot.backdrop = probe->backdrop->mirror.name();
            const Probe* p = &*probe;
            slot.drawFace = [this, p, &models, items, &environment, &meshes, &shadows, &camera, &stats](int face) {
                drawProbeFace(*p, face, false, p->phantoms, models, items, environment, meshes, shadows, camera, stats);
            };
            updatedSlots_.push_back(int(k));
            const EnvironmentMapReads reads = itemReads_[probe->owner];
            builtReads_[object] = reads;
            if (reads.diffuse)
                shSlots_.push_back(int(k));
            if (reads.glossy1 || reads.glossy2)
                glossySlots_.push_back(int(k));
            if (reads.glossy1)
                glossy1Slots_.push_back(int(k));
        } else if (probes_[object].ready) {
            // Not updated: its last maps carried over into the texture drawn now.
            slot.backdrop = bank.previousMirror.name();
            slot.backdropIsBank = true;
        } else {
            continue;
        }
        mirrorSlots_.push_back(std::move(slot));
    }
    pipeline_.renderMirrorSlots(bank.maps, mirrorSlots_);
    timer.split(stats.environmentMaps);
    pipeline_.projectSHSlots(bank.maps, shSlots_);
    timer.split(stats.sh);
    pipeline_.prefilterSlots(bank.maps, glossySlots_, glossy1Slots_);
    timer.split(stats.prefilter);
    pointViews(bank.maps.mirror.name());
    for (const int k : updatedSlots_)
        probes_[bank.objects[size_t(k)]].ready = true;
    stats.shProjected += int(shSlots_.size());
    stats.mapsPrefiltered += int(glossySlots_.size());
    stats.mapsUpdated += int(updatedSlots_.size());
}

std::span<const IblMaps* const>
EnvironmentProbes::update(const std::vector<GpuModel>& models, std::span<const DrawItem> items,
                          const EnvironmentLighting& environment, const MeshPass& meshes, const ShadowPass& shadows,
                          const CameraView& camera, RenderCpuClock* profile, RenderStats& stats)
{
    if (environment.generation() != environmentGeneration_)
        rebuildEnvironmentMaps(environment);

    // Each owner's reads, once a frame (renderBank records them as built). An object whose
    // materials now read maps its set was not built with (a material edited from chrome to
    // paint) shows the real environment's maps until its own are rebuilt with them, as a new
    // object does: never maps that were never drawn.
    itemReads_.assign(items.size(), EnvironmentMapReads{});
    for (size_t i = 0; i < items.size(); ++i) {
        const DrawItem& item = items[i];
        if (item.object < 0 || item.phantom)
            continue;
        itemReads_[i] = environmentMapReads(models[size_t(item.model)]);
        const auto probe = probes_.find(item.object);
        if (probe != probes_.end() && probe->second.ready && !builtReads_[item.object].covers(itemReads_[i]))
            probe->second.ready = false;
    }
    maps_.resize(items.size());
    for (size_t i = 0; i < items.size(); ++i) {
        const IblMaps* own =
            options_.dynamic && items[i].object >= 0 && !items[i].phantom ? objectMaps(items[i].object) : nullptr;
        maps_[i] = own ? own : &environmentMaps_;
    }
    if (options_.dynamic) {
        chooseUpdates(models, items, environment);
        const bool timeProbes = options_.policy == EnvironmentMapPolicy::Budget;
        int unslotted = 0; // map owners without a slot: what a new bank is sized for
        for (const size_t i : owners_)
            unslotted += hasSlot(items[i].object) ? 0 : 1;
        for (const size_t i : updates_)
            if (!hasSlot(items[i].object))
                slotOf(items[i].object, unslotted--);
        for (size_t b = 0; b < banks_.size(); ++b) {
            bankUpdates_.clear();
            for (const size_t i : updates_)
                if (slotOf(items[i].object).first == b)
                    bankUpdates_.push_back(i);
            if (bankUpdates_.empty())
                continue;
            const double before = stats.environmentMaps.wallMs + stats.sh.wallMs + stats.prefilter.wallMs;
            renderBank(b, bankUpdates_, models, items, environment, meshes, shadows, camera, profile,
                       profile != nullptr || timeProbes, stats);
            if (timeProbes) {
                const double cost = (stats.environmentMaps.wallMs + stats.sh.wallMs + stats.prefilter.wallMs - before) /
                                    double(bankUpdates_.size());
                probeCostMs_ = probeCostMs_ > 0.0 ? 0.8 * probeCostMs_ + 0.2 * cost : cost;
            }
            // From now on this frame (later banks and the frame itself) sees the new maps.
            for (const size_t i : bankUpdates_)
                maps_[i] = &probes_[items[i].object];
        }
    }
    ++frame_;
    return maps_;
}

} // namespace lumar
