// The per-object dynamic environment maps of the paper (DESIGN.md §6.1): each scene object
// owns an IblMaps set rendered from its bounding-box centre with itself hidden, holding the
// real-environment skybox and the other objects shaded with their own maps as they stand
// (one bounce of inter-reflection per frame). Which maps are re-rendered each frame follows
// the configured policy; an object whose maps are not ready is lit by the real environment.
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
        history_.clear();
        phantomLayers_.clear();
    }

private:
    void rebuildEnvironmentMaps(const EnvironmentLighting& environment);
    // Which items get new maps this frame (indices into items).
    void chooseUpdates(const std::vector<GpuModel>& models, std::span<const DrawItem> items,
                       const EnvironmentLighting& environment);
    void renderProbe(size_t owner, const std::vector<GpuModel>& models, std::span<const DrawItem> items,
                     const EnvironmentLighting& environment, const MeshPass& meshes, const ShadowPass& shadows,
                     const CameraView& camera, RenderCpuClock* cpu, bool finish, RenderStats& stats);

    EnvironmentMapOptions options_;
    IblPipeline pipeline_;
    IblMaps environmentMaps_;
    int environmentGeneration_ = -1;
    std::map<int, IblMaps> probes_; // by DrawItem::object; node-based: pointers stay valid
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
    std::vector<DrawItem> faceItems_;
    std::vector<const IblMaps*> faceMaps_;
};

} // namespace lumar
