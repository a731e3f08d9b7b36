// Shadows of the dominant light (DESIGN.md §6.5). A depth-only pass draws the virtual objects
// (the casters) as the light sees them, with an orthographic camera fitted to their bounding
// boxes, when they or the light changed (whole, or the part an animated caster moves in);
// every view (the frame, the cube faces of the environment maps) then looks its points up in
// that map through FrameUniforms' light members (fillView), so virtual objects shadow each
// other in mesh.frag. In the frame, the phantoms and the receiver-only surfaces are drawn by
// drawReceivers instead of depth-only: they darken the camera image by the share of light the
// objects take from them (shadow) and the contact occlusion of the objects standing on them
// (phantom_receiver.frag).
#pragma once

#include <array>
#include <cstdint>
#include <limits>
#include <span>
#include <vector>

#include "gles_renderer/gl/gl_object.h"
#include "gles_renderer/gl/render_cpu_clock.h"
#include "gles_renderer/ibl_gpu/ibl_maps.h"
#include "gles_renderer/scene/gpu_model.h"
#include "gles_renderer/scene/pixel_rects.h"
#include "gles_renderer/scene/scene_renderer.h"
#include "gles_renderer/scene/tile_cover.h"
#include "gles_renderer/scene/uniform_blocks.h"

namespace lumar {

class ShadowPass {
public:
    // Creates the map (a 1 x 1 stand-in when shadows are off, so the mesh program always has
    // a depth texture bound) and the programs. Throws RuntimeError when GL cannot.
    explicit ShadowPass(const ShadowOptions& options);

    [[nodiscard]] bool enabled() const { return options_.enabled; }
    // Environment frame. Throws InputError for a zero or non-finite direction, or a negative
    // or non-finite colour or intensity.
    void setLight(const DirectionalLight& light);

    // Prepares this frame's map from `items` (casters: the items that are not phantoms), the
    // light turned into the frame's camera frame by `environmentFromCamera`. The map is fitted
    // and drawn in a frame that moves with the scene, not the camera (LightFit), and drawn only
    // when something it depends on changed: the light's direction, a caster's pose relative to
    // the others or to the environment, an animated caster's pose (GpuModel::poseGeneration),
    // the receivers' reach in depth. stats.shadowMapDrawn says how much was drawn. May leave
    // the GL framebuffer binding and viewport changed. Does nothing when shadows are off.
    void render(const std::vector<GpuModel>& models, std::span<const DrawItem> items,
                const glm::dmat3& environmentFromCamera, RenderCpuClock* profile, RenderStats& stats);
    // Forgets the map, so that the next render draws it whole: the models it was drawn from
    // are gone (their indices may name new ones).
    void invalidate() { drawn_ = false; }

    // Writes the light's members of `frame` for a view whose camera frame sits at
    // `cameraFromView` in the frame's camera frame (identity for the frame itself). Leaves them
    // zero (no light, no shadows: today's shading) when shadows are off.
    void fillView(FrameUniforms& frame, const glm::dmat4& cameraFromView) const;

    // The shadow map: a depth texture with GL_COMPARE_REF_TO_TEXTURE and GL_LINEAR filtering.
    [[nodiscard]] GLuint map() const { return map_.name(); }

    // Into the bound framebuffer (the frame, its viewport set), over the camera image: the
    // phantoms' depth, only where a later pass reads it (where the virtual objects' boxes are
    // seen and where the darkening is applied: a pass that draws elsewhere against the
    // phantoms must widen depthRects), and the darkening of the phantoms and then of the receiver-only items
    // (where no phantom is in front), item i with maps[i]'s diffuse map as its real
    // irradiance. The darkening is shaded at 1 / ShadowOptions::receiverScale of the frame's resolution (see
    // RatioBuffer) and multiplied into the frame. `frame` must have been filled by fillView
    // for the frame. Does nothing when shadows are off.
    void drawReceivers(const FrameUniforms& frame, const std::vector<GpuModel>& models, std::span<const DrawItem> items,
                       std::span<const IblMaps* const> maps);

    // Texture unit of the darkening while it is applied to the frame.
    static constexpr GLuint kRatioUnit = 14;
    // The darkening is smooth (a PCF penumbra, contact occlusion falling off over the objects'
    // size), so ShadowOptions::receiverScale defaults to 2: shaded at half the frame's width
    // and height it costs a quarter. car.toml at 1280x720 on llvmpipe, rasteriser CPU time a
    // frame, load 10: the receivers 92 ms at full resolution (the shader over the ~770,000
    // pixels where shadows or contacts can fall), 31 ms at half (22 ms of it the shader, 6 ms
    // applying the buffer to the frame, 2 ms the phantoms' depth), 16 ms at quarter. Against
    // full resolution, half changes 0.05 % of the frame's pixels by more than 8 code values
    // (edges: a real box's outline against its shadow), quarter 0.4 %. Since the apply pass
    // upsamples depth-aware (shadow_apply.frag), a shadow no longer crosses a real box's
    // outline at half or quarter (Shadows.TheUpsampledDarkeningKeepsToItsSurfaceAtADepthEdge);
    // on car.toml (one table, no depth edge inside it) half and quarter differ from full as
    // before (0.034 % and 0.28 % of pixels by more than 8: the virtual objects' feet), and
    // full is bit-identical to the plain filter. Its cost, car.toml, load 15-25, medians of 3
    // interleaved: the receivers 31 -> 36 ms CPU at half, 16 -> 21 ms at quarter. Culled to the
    // tiles where a shadow or a contact can fall (darkenedCover: 44 % of car.toml's buffer
    // against 87 % for the places' bounding rectangles), quarter, medians of 3 interleaved,
    // load 3-4: the receivers 30.6 -> 20.9 ms CPU (15.7 -> 11.0 wall); tiles of 16 and 32 px
    // measured alike, 64 and 128 px dearer (more area). Split by glFinish, one convex phantom
    // (APPLY_ONE_SURFACE's first step, four fetches), CPU ms a frame: the distances 0.6, the
    // darkening 3.9 (half of it its shader), the depth 0.3, applying 4.6 over the ~400,000
    // pixels of the darkening's tiles, three quarters of which the darkening reaches (so a
    // tighter cover saves little there); the shader's own share of it is small, the pass is
    // the pixels' rasterisation, depth and blend. Measured and not taken (2026-12-05, car.toml
    // with bloom, replay, interleaved): multiplying the darkening into the camera image on the
    // CPU as it is uploaded, instead of the apply pass (the buffer read back, the silhouette
    // of the one convex phantom for its coverage, the image expanded and darkened on two
    // threads; 14,888 pixels off by one code value, none by more). The pass's ~4 ms of
    // rasteriser CPU went, but the multiplication cost ~1.7 ms and the readback is a wait for
    // everything queued: where the wait came early in the frame the rasteriser's threads
    // idled through the darkening's 15 tiles (33.6/32.4/33.1 -> 33.1/32.2/33.2 fps), placed
    // after the environment maps 33.1/33.1/33.3 -> 31.4/31.1/31.1 fps.

private:
    // The darkening, shaded at a fraction of the frame's resolution: an RGBA8 texture, red
    // the ratio (encoded as phantom_receiver.frag writes it), green and blue the receiver's
    // distance from the camera (receiver_distance.glsl, for shadow_apply.frag's depth-aware
    // upsampling), alpha 1 where a receiver is; cleared to (0, 1, 1, 0) (no receiver: red and
    // alpha 0, so that red is the ratio premultiplied by the coverage, which a GL_LINEAR lookup
    // filters as APPLY_ONE_SURFACE needs), and a depth buffer for the phantoms at that resolution.
    struct RatioBuffer {
        int frameWidth = 0, frameHeight = 0;
        int scale = 1; // frame pixels per texel along x and y
        GlTexture colour;
        GlRenderbuffer depth;
        GlFramebuffer framebuffer;
    };
    // (Re)creates ratio_ for a frame of this size.
    void prepareRatioBuffer(int frameWidth, int frameHeight);
    void linkApplyPrograms();
    // The light's orthographic camera, in the "stable" frame: the environment's axes (the
    // camera's rotation in them is environmentFromCamera) with its origin at the first caster's
    // model origin. The casters (on one marker) and the light (from the environment) stand still
    // in it while the real camera moves, so a map drawn in it stays valid.
    struct LightFit {
        glm::dmat4 lightViewFromStable{1.0};
        glm::dmat4 lightClipFromStable{1.0};
        glm::dvec2 centre{0.0}; // of the map, light view frame
        double side = 0.0, nearZ = 0.0, farZ = 0.0;
        double texelMetres = 0.0;
        double depthBias = 0.0;
        // Each caster's box in the light's view frame, reaching to the map's far end: the
        // shadow it casts lies inside.
        std::vector<std::pair<glm::dvec3, glm::dvec3>> prisms;
    };
    // What a caster's depth in the map depends on besides the fit, and where it lies in it.
    struct CasterKey {
        int model = -1;
        uint64_t poseGeneration = 0;
        glm::dmat4 stableFromModel{1.0};
        // Its box's extent across the light (light view x and y; empty when not finite).
        glm::dvec2 low{std::numeric_limits<double>::infinity()};
        glm::dvec2 high{-std::numeric_limits<double>::infinity()};
        // A model posed by node transforms alone (GpuModel::pose, nothing deforms): each of
        // its primitives' pose and box across the light, by GpuPrimitive::source. A new pose
        // then draws again only where the primitives it moved were and are (a truck's wheels,
        // not the truck). Empty for other models: their whole box.
        std::vector<glm::dmat4> primitivePoses;
        std::vector<std::pair<glm::dvec2, glm::dvec2>> primitiveBoxes;
    };
    // `key`'s per-primitive poses and boxes across the light (light view x and y), for a model
    // posed by its nodes' transforms alone (no skin or morph target deforms a primitive).
    static void describePrimitives(const GpuModel& model, const glm::dmat4& lightViewFromModel, CasterKey& key);
    // Fits the light's camera to `items`' casters (and receivers in depth), given in the stable
    // frame by `stableFromCamera`, and describes each caster (in `items`' order); false when
    // there is nothing to cast a shadow.
    bool fitLightCamera(const std::vector<GpuModel>& models, std::span<const DrawItem> items,
                        const glm::dmat4& stableFromCamera, LightFit& fit, std::vector<CasterKey>& casters) const;
    // What of the map drawn (fit_, drawnCasters_) differs from the one `fit` and `casters`
    // would draw: nothing, the texels of `parts` (disjoint; where animated casters, or the
    // primitives their nodes moved, were and are: only their poses changed), or all.
    enum class Redraw { None, Part, All };
    [[nodiscard]] Redraw compareMap(const LightFit& fit, const std::vector<CasterKey>& casters,
                                    std::vector<PixelRect>& parts) const;
    // The map's texels (with a margin) that the light view rectangle [low, high] touches.
    [[nodiscard]] PixelRect texelsOf(const glm::dvec2& low, const glm::dvec2& high) const;
    void linkDepthProgram();
    void linkReceiverPrograms();
    // Draws the map from fit_ and drawnCasters_: whole, or (`part` not null) only the texels of
    // `part`, cleared and drawn again from the casters (and where known, their primitives)
    // that reach into it.
    void drawCasters(const std::vector<GpuModel>& models, std::span<const DrawItem> items, const PixelRect* part) const;
    // Works out this frame's occluders (occluders_, reachBoxes_).
    void setOccluders(const std::vector<GpuModel>& models, std::span<const DrawItem> items);
    // Where in the viewport the receivers can be darkened: the tiles (tile_cover.h) that the
    // parts of each receiver inside a caster's prism along the light, or within reach of an
    // occluder, touch (all of it without ShadowOptions::cullReceivers), each labelled with
    // what reaches it: bit i occluder i (occluders_), kShadowLabel a prism.
    [[nodiscard]] TileCover darkenedCover(const FrameUniforms& frame, const std::vector<GpuModel>& models,
                                          std::span<const DrawItem> items) const;
    static constexpr uint32_t kShadowLabel = 1u << 16;

    ShadowOptions options_;
    int size_;
    DirectionalLight light_;
    bool lightSet_ = false;
    // This frame's light, in the frame's camera frame.
    glm::dvec3 lightDirection_{0.0, 0.0, -1.0};
    glm::dmat4 lightClipFromCamera_{1.0};
    glm::dmat4 lightViewFromCamera_{1.0};
    bool mapValid_ = false;
    // What the map holds: drawn (drawn_) with fit_ from drawnCasters_ under the light from
    // drawnLightDirection_ (environment frame).
    LightFit fit_;
    std::vector<CasterKey> drawnCasters_;
    std::vector<PixelRect> parts_; // compareMap's, kept: no allocation a frame
    glm::dvec3 drawnLightDirection_{0.0};
    bool drawn_ = false;
    // This frame's, compared with those (kept to reuse their storage).
    LightFit freshFit_;
    std::vector<CasterKey> freshCasters_;

    GlTexture map_;
    GlFramebuffer framebuffer_;
    GlProgram depthProgram_;
    GLint depthCameraFromMeshLocation_ = -1;
    // depth_only with ALPHA_CUTOUT, for MASK and BLEND materials, transmissive or not (cut
    // out, and dithered by their opacity: translucent casters cast partial shadows; other
    // glass is dithered by the map's stencil, drawCasters); [1] reads the base
    // colour texture (on this unit), [0] is for materials without one.
    static constexpr GLuint kCutoutTextureUnit = 0;
    struct CutoutProgram {
        GlProgram program;
        GLint cameraFromMesh = -1;
    };
    // Linked at first use (cutoutProgram), from the const drawCasters: a cache.
    mutable CutoutProgram cutoutPrograms_[2];
    mutable bool partClearCompiled_ = false; // drawCasters' scissored clear has been drawn
    [[nodiscard]] const CutoutProgram& cutoutProgram(bool textured) const;
    // phantom_receiver.frag: [1] with the shadow map's lookups, for the tiles a prism
    // reaches; [0] without them (RECEIVER_SHADOW 0), for those only occluders reach, where
    // the lookups would all find the light unblocked. (llvmpipe runs every lookup and every
    // occluder's term for every pixel: a block takes all branches any of its pixels takes.)
    struct DarkeningProgram {
        GlProgram program;
        GLint cameraFromMesh = -1;
        GLint normalFromMesh = -1;
        GLint occluderCount = -1;
        GLint unitFromCamera = -1;
        GLint unitNormalFromCamera = -1;
        GLint occluderReach = -1;
    };
    DarkeningProgram darkeningPrograms_[2];
    // Sets the darkening program's (in use) occluders to those of occluders_ that `label`
    // names, in their order: the others' terms are exactly 1 in its tiles.
    void useOccluders(const DarkeningProgram& program, uint32_t label) const;
    // phantom_receiver.frag's kMaxOccluders: objects beyond it darken no contact (the first
    // ones in draw order are kept). At most 16: kShadowLabel is the next bit.
    static constexpr int kMaxOccluders = 16;
    // This frame's occluders, as phantom_receiver.frag takes them (setOccluders).
    struct Occluders {
        int count = 0;
        std::array<glm::mat4, kMaxOccluders> unitFromCamera{};
        std::array<glm::mat3, kMaxOccluders> unitNormalFromCamera{};
        std::array<glm::vec4, kMaxOccluders> reach{};
    };
    Occluders occluders_;
    GlProgram receiverDepthProgram_;
    GLint receiverDepthCameraFromMeshLocation_ = -1;
    GLint receiverDepthNormalFromMeshLocation_ = -1;
    // This frame's occluders: the camera frame from the space where each one's ellipsoid is
    // the unit sphere (its reach is the cube of side 2 kOcclusionReach there).
    std::vector<glm::dmat4> reachBoxes_;
    GlBuffer frameUniforms_;
    RatioBuffer ratio_;
    GlProgram receiverDistanceProgram_;
    GLint receiverDistanceCameraFromMeshLocation_ = -1;
    GLint receiverDistanceNormalFromMeshLocation_ = -1;
    // shadow_apply.frag: [0] over the phantoms' depth (GL_EQUAL) and the receiver-only
    // surfaces, leaving the pixels it does not darken alone (discard); [1] (APPLY_WRITES_DEPTH)
    // writing the phantom's depth as it applies, every pixel (a ratio of 1 where it darkens
    // nothing: the blend leaves the pixel exactly as it was); [2] that (APPLY_ONE_SURFACE),
    // where the phantom is the buffer's one receiver (applyOneSurface).
    struct ApplyProgram {
        GlProgram program;
        GLint cameraFromMesh = -1;
        GLint normalFromMesh = -1;
        GLint texelsPerPixel = -1;
    };
    ApplyProgram applyPrograms_[3];
    // Whether the apply pass can write the phantoms' depth itself (GL_LESS, one pass instead
    // of a depth pass and a GL_EQUAL one): exactly where each pixel meets at most one phantom
    // fragment, or the farther one would be darkened too and the nearer one over it. So: one
    // phantom (not receiver-only) among `items`, single-sided (back faces culled), not posed
    // (its vertices stay), and convex (GpuModel::convex).
    [[nodiscard]] static bool applyCanWriteDepth(const std::vector<GpuModel>& models, std::span<const DrawItem> items);
    // applyCanWriteDepth, and no receiver-only surface: the darkening buffer's texels hold
    // that phantom or no receiver, and the apply pass needs no distances to tell its own.
    [[nodiscard]] static bool applyOneSurface(const std::vector<GpuModel>& models, std::span<const DrawItem> items);
};

} // namespace lumar
