// The per-object dynamic environment maps of the paper (DESIGN.md §6.1): each scene object
// owns an IblMaps set rendered from its bounding-box centre with itself hidden, holding the
// real-environment skybox and the other objects shaded with their own maps as they stand
// (one bounce of inter-reflection per frame). Which maps are re-rendered each frame follows
// the configured policy; an object whose maps are not ready is lit by the real environment.
// The objects' maps live in banks (ibl_maps.h): the maps of up to kBankSlots objects are
// drawn in one pass per kind, so each face sees its neighbours as the previous frame left
// them (DESIGN.md §6.1), read from the bank's other mirror texture.
#pragma once

#include <cstdint>
#include <functional>
#include <map>
#include <span>
#include <utility>
#include <vector>

#include "gles_renderer/gl/render_cpu_clock.h"
#include "gles_renderer/ibl_gpu/environment_lighting.h"
#include "gles_renderer/ibl_gpu/ibl_pipeline.h"
#include "gles_renderer/scene/camera_image.h"
#include "gles_renderer/scene/gpu_model.h"
#include "gles_renderer/scene/mesh_pass.h"
#include "gles_renderer/scene/scene_renderer.h"
#include "gles_renderer/scene/shadow_pass.h"

namespace lumar {

// The Frame uniforms of cube face `face` (cube_face_camera.h) of a map `size` texels square:
// the face camera's projection, its axes in the environment frame, a mirrored frame (the
// faces' cameras are) that writes linear radiance, RGBM-encoded where `rgbm`, at exposure 1.
// No light: ShadowPass::fillView adds the view's.
FrameUniforms cubeFaceFrameUniforms(int face, int size, bool rgbm);

class EnvironmentProbes {
public:
    explicit EnvironmentProbes(const EnvironmentMapOptions& options);

    // Brings the maps up to date for this frame and returns, per item, the maps that shade
    // it (valid until the next call). Rebuilds the real environment's own maps when it
    // changed. `shadows` gives each face its view of this frame's shadow map; `camera`: this
    // frame's camera image, which phantoms carry in the maps where it and the phantoms' depth
    // (CameraView::phantomDepth) are given. Leaves the GL framebuffer binding and viewport
    // changed.
    std::span<const IblMaps* const> update(const std::vector<GpuModel>& models, std::span<const DrawItem> items,
                                           const EnvironmentLighting& environment, const MeshPass& meshes,
                                           const ShadowPass& shadows, const CameraView& camera, RenderCpuClock* profile,
                                           RenderStats& stats);

    [[nodiscard]] const IblMaps* objectMaps(int object) const;
    [[nodiscard]] const IblMaps& environmentMaps() const { return environmentMaps_; }
    // Whether the maps are RGBA8 RGBM (no float render targets): shaders decode them.
    [[nodiscard]] bool rgbm() const { return pipeline_.rgbm(); }
    // Renders the real environment's maps with drawSkybox(face) as every face's content (the
    // environment built from the camera) instead of from `environment`'s map; update() keeps
    // them until `environment` changes again. The objects' maps are kept (an environment that
    // changes every few frames must not throw them away): they take the new maps as their
    // backdrop at their next update, which the on_change policy schedules.
    void refreshEnvironmentMaps(const EnvironmentLighting& environment,
                                const std::function<void(int face)>& drawSkybox);
    // The next update() rebuilds the real environment's maps from the environment's map.
    void markEnvironmentStale() { environmentGeneration_ = -1; }
    // Forgets every object's maps (the models they showed are gone).
    void clear()
    {
        probes_.clear();
        builtReads_.clear();
        history_.clear();
        phantomLayers_.clear();
        for (Bank& bank : banks_)
            bank.objects.assign(bank.objects.size(), -1);
    }
    // As if no frame had been drawn: clear(), and the update schedules start again.
    void forgetFrames()
    {
        clear();
        frame_ = 0;
        roundRobin_ = 0;
    }
    // Objects per bank (fewer where the mirror maps are large: a bank stays within 2048 px).
    static constexpr int kBankSlots = 4;

private:
    void rebuildEnvironmentMaps(const EnvironmentLighting& environment);
    // Which items get new maps this frame (indices into items).
    void chooseUpdates(const std::vector<GpuModel>& models, std::span<const DrawItem> items,
                       const EnvironmentLighting& environment);
    // One object's part of its bank's mirror pass: the backdrop of its map (the real
    // environment's, or its phantom layer, drawn here where stale) and how its faces draw
    // the phantoms.
    struct Probe {
        size_t owner = 0; // index into items
        glm::dvec3 centre{0.0};
        const IblMaps* backdrop = nullptr;
        MeshPass::Phantoms phantoms = MeshPass::Phantoms::Shaded;
    };
    Probe prepareProbe(size_t owner, const std::vector<GpuModel>& models, std::span<const DrawItem> items,
                       const EnvironmentLighting& environment, const MeshPass& meshes, const ShadowPass& shadows,
                       const CameraView& camera, RenderStats& stats);
    // Draws face `face` of `probe`'s map: the items but its owner (or the phantoms alone).
    void drawProbeFace(const Probe& probe, int face, bool phantomsOnly, MeshPass::Phantoms phantoms,
                       const std::vector<GpuModel>& models, std::span<const DrawItem> items,
                       const EnvironmentLighting& environment, const MeshPass& meshes, const ShadowPass& shadows,
                       const CameraView& camera, RenderStats& stats);
    // Renders the maps of the listed updates (indices into items) of bank `bank`, all in
    // one pass per kind.
    void renderBank(size_t bank, std::span<const size_t> updates, const std::vector<GpuModel>& models,
                    std::span<const DrawItem> items, const EnvironmentLighting& environment, const MeshPass& meshes,
                    const ShadowPass& shadows, const CameraView& camera, RenderCpuClock* cpu, bool finish,
                    RenderStats& stats);
    // The bank and slot of `object`'s maps, given one where it has none yet. A new bank
    // gets `wanted` slots (at most kBankSlots): the objects still without one, so a scene
    // of fewer objects does not pay for kBankSlots sets of maps.
    std::pair<size_t, int> slotOf(int object, int wanted = kBankSlots);
    [[nodiscard]] bool hasSlot(int object) const;

    EnvironmentMapOptions options_;
    IblPipeline pipeline_;
    IblMaps environmentMaps_;
    int environmentGeneration_ = -1;
    // Banks of objects' maps. maps.mirror holds the mirror maps drawn last; previousMirror
    // those of the pass before, which the next pass's faces read while it draws maps.mirror.
    struct Bank {
        IblMaps maps;
        GlTexture previousMirror;
        std::vector<int> objects; // per slot: the object, or -1
    };
    std::vector<Bank> banks_;
    // Per object: a view of its slot (IblMaps::view). By DrawItem::object; node-based:
    // pointers stay valid.
    std::map<int, IblMaps> probes_;
    // Per object: which of its derived maps its set holds (the last update's reads).
    std::map<int, EnvironmentMapReads> builtReads_;
    // OnChange: what each object's map last saw, and the updates still owed to the bounces.
    struct History {
        std::vector<glm::dmat4> scene;
        uint64_t poses = 0; // the sum of the items' GpuModel::poseGeneration
        int bouncesLeft = 0;
    };
    std::map<int, History> history_;
    // Per object: the skybox with the phantoms drawn over it, as seen from the object's
    // centre, the backdrop of its map while the phantoms stay where they were relative to
    // it. A phantom is a large shaded surface (a table fills a hemisphere of the map) lit by
    // the real environment's maps alone, so it looks the same until it moves relative to
    // the centre or the environment changes; each update then draws it into depth only
    // (it still hides the neighbours behind it) instead of shading thousands of texels.
    // The layer is drawn once the phantoms have stood still for two updates: phantoms that
    // keep moving relative to the object are shaded into its map directly, as before.
    // Only for phantoms in their configured colour: phantoms that carry the camera image
    // (phantom.frag) change with every frame, so they are always drawn directly.
    // The virtual objects' shadows on the phantoms are in the layer as they were when it was
    // drawn: objects standing on the phantoms' marker keep them; others moving over them
    // leave them stale until a phantom moves.
    struct PhantomLayer {
        IblMaps maps; // only the mirror map is used
        bool drawn = false;
        std::vector<std::pair<int, glm::dmat4>> phantoms; // model, environment-frame pose relative to the centre
    };
    std::map<int, PhantomLayer> phantomLayers_;            // by DrawItem::object
    std::vector<std::pair<int, glm::dmat4>> phantomScene_; // per-probe scratch
    std::vector<glm::dmat4> scene_;                        // this frame's scene in the environment frame
    long frame_ = 0;
    size_t roundRobin_ = 0;
    double probeCostMs_ = 0.0; // running mean cost of one probe (budget policy)
    // Per-frame scratch, kept to avoid allocating every frame.
    std::vector<const IblMaps*> maps_;
    std::vector<size_t> updates_;
    std::vector<size_t> owners_;
    std::vector<Probe> probesThisPass_;
    std::vector<IblPipeline::MirrorSlot> mirrorSlots_;
    std::vector<int> updatedSlots_;
    std::vector<EnvironmentMapReads> itemReads_; // per item: the maps an owner's materials read
    std::vector<int> shSlots_;                   // of updatedSlots_: the objects that read the diffuse map
    std::vector<int> glossySlots_;               // ... a glossy map (glossy-2 is glossy-1's source)
    std::vector<int> glossy1Slots_;              // ... glossy-1
    std::vector<size_t> bankUpdates_;
    std::vector<DrawItem> faceItems_;
    std::vector<const IblMaps*> faceMaps_;
};

} // namespace lumar
