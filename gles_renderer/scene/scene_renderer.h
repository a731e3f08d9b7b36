// The rendering stage: draws glTF models over the camera image into an offscreen
// framebuffer on a surfaceless EGL/GLES 3 context, and reads the result back.
#pragma once

#include <memory>
#include <span>

#include <glm/glm.hpp>

#include "core/camera_model.h"
#include "core/image.h"
#include "core/ycbcr_image.h"
#include "gles_renderer/assets/environment_map.h"
#include "gles_renderer/assets/gltf_model.h"
#include "gles_renderer/assets/model_pose.h"
#include "gles_renderer/ibl_gpu/ibl_maps.h"
#include "gles_renderer/overlay/overlay_scene.h"

namespace lumar {

class EglDisplay;
class WindowTarget;

using ModelId = int;

struct DrawItem {
    ModelId model = -1;
    // Model space to the OpenCV camera frame (x right, y down, z forward), metres.
    glm::dmat4 cameraFromModel{1.0};
    // A stable id of the scene object this item draws (>= 0): it owns a dynamic environment
    // map kept from frame to frame. -1: lit by the real environment alone.
    int object = -1;
    // A proxy of a real object (DESIGN.md §6.5): it writes depth in the frame (virtual
    // objects behind it are hidden, the camera image shows through) and is drawn, lit, in
    // the environment maps (virtual objects reflect it), carrying the camera image there.
    bool phantom = false;
    // With `phantom`: a surface that only receives (DESIGN.md §6.5), e.g. the table under the
    // objects where it has no phantom of its own. In the frame it darkens the camera image
    // with the objects' shadows and contact occlusion where no phantom stands in front of it,
    // writes no depth, and it is left out of the environment maps. Drawn only with shadows on.
    bool receiverOnly = false;
};

// The dominant light (DESIGN.md §6.5): a share of the real environment's light coming from
// one direction. It adds nothing: shadows remove it where the shadow map says it is blocked.
struct DirectionalLight {
    glm::dvec3 direction{0.0, 1.0, 0.0}; // towards the light, environment frame (+Y up); non-zero
    glm::vec3 color{1.0f};               // linear
    // colour * intensity is the irradiance on a surface facing the light, in the environment
    // map's radiance units times steradians (a uniform sky of radiance L gives the ground pi L).
    float intensity = 0.0f; // 0: no light (contact darkening only)
};

// Shadow maps and contact darkening (DESIGN.md §6.5). Off unless asked for: the app turns
// them on from [shadows].
struct ShadowOptions {
    bool enabled = false;
    int mapSize = 1024;    // texels per side
    float softness = 1.5f; // PCF kernel radius, texels (0: the bilinear 2x2 comparison alone)
    // Frame pixels per texel, along x and y, of the buffer the real surfaces' darkening is
    // shaded in (1, 2 or 4; ShadowPass, by its kRatioUnit, says why 2).
    int receiverScale = 2;
    // Shade the darkening only in the tiles where a shadow or a contact can fall (ShadowPass);
    // false shades the whole buffer, a reference for tests.
    bool cullReceivers = true;
};

// Lens effects on the virtual objects' light (DESIGN.md §6.5, gles_renderer/scene/lens_effects.h):
// what is brighter than `threshold` (radiance times exposure, where the camera's response
// reaches 1 only at infinity) spreads around it as bloom and as glare streaks, added to the
// frame as light scattered in the lens. Off unless asked for: the app turns them on from
// [rendering.lens]; off, the frame is drawn as without them and nothing is spent on them.
// The format of the lens effects' pyramid: RGBA16F (where a float format renders) or RGBA8
// RGBM. Auto: RGBM on a software rasteriser, where llvmpipe sampled RGBA16F 3.5x slower
// (the full-size composite of the demo truck at 1280x720, load 8: 63 ms against 18 ms).
enum class LensImageFormat { Auto, Float, Rgbm };
// Where the effects are computed past the bright pass. Culled: the half-size bright image is
// read back (one wait for the rasteriser) and the bloom, the glare, the frame's copy and the
// composite are drawn only in the 32-pixel tiles within their reach of a bright texel; the
// frame is the same as Whole's. Auto: Culled on a software rasteriser, where every pixel drawn
// costs CPU time (the car scene with bloom: 2.4 % of the pixels change, in 48 of 880 tiles)
// and a readback costs little; Whole on a GPU, which a readback would stall.
enum class LensCulling { Auto, Whole, Culled };

struct LensOptions {
    bool enabled = false;
    LensImageFormat images = LensImageFormat::Auto;
    LensCulling culling = LensCulling::Auto;
    float threshold = 1.0f; // the bright pass: light above this feeds bloom and glare
    bool bloom = true;
    float bloomIntensity = 0.5f; // share of the bright light spread as bloom (1: all of it)
    float bloomRadius = 32.0f;   // output pixels the bloom reaches
    bool glare = false;
    int glareStreaks = 4;        // rays from each bright spot, evenly spaced (2..16)
    float glareLength = 96.0f;   // output pixels a ray reaches
    float glareIntensity = 0.3f; // share of the bright light spread along the rays
    float glareAngle = 0.0f;     // degrees, the first ray's angle from +x (image right), towards +y (down)
};

// When the per-object environment maps are re-rendered (DESIGN.md §6.1).
enum class EnvironmentMapPolicy {
    EveryFrame,   // every object's map, every frame (the paper's method)
    EveryKFrames, // each object every k-th frame, objects staggered across frames
    Budget,       // round-robin, as many as fit a per-frame time budget (at least one)
    OnChange,     // when the scene around the object changed, then a few more frames for the
                  // inter-reflection bounces to settle; the same images as EveryFrame
};

struct EnvironmentMapOptions {
    bool dynamic = true; // false: every object is lit by the real environment alone
    EnvironmentMapPolicy policy = EnvironmentMapPolicy::EveryFrame;
    int everyK = 2;
    double budgetMs = 8.0;
    // Phantoms in the maps carry the camera image where the camera saw them (DESIGN.md §6.1);
    // false: their configured colour everywhere (cheaper: drawn once while they stand still).
    bool phantomsShowCamera = true;
    IblSettings ibl;
};

// One stage's cost in the last frame: wall-clock milliseconds, and milliseconds of CPU time
// of the rendering threads (on llvmpipe, the rasteriser's threads: the rendering work itself,
// which a loaded machine hardly changes; on a GPU, the driver's CPU time alone).
struct StageTime {
    double wallMs = 0;
    double cpuMs = 0;
};

// The last frame's stages, measured only with RenderOptions::profile (it waits for the GPU
// between stages, which a real GPU would otherwise overlap); `animation` is CPU work and is
// timed always.
struct RenderStats {
    int mapsUpdated = 0;
    // Of those, the sets whose SH projection and diffuse map, and whose glossy maps, were
    // rebuilt: only where the object's materials read them (EnvironmentMapReads).
    int shProjected = 0;
    int mapsPrefiltered = 0;
    int facesCulled = 0;       // objects left out of cube faces they cannot appear in
    StageTime environmentMaps; // cube faces: skybox and the other objects
    StageTime sh;              // SH projection and the diffuse map
    StageTime prefilter;       // the glossy maps
    StageTime background;      // the camera image drawn, kept for the maps, the phantoms' depth
    StageTime shading;         // the objects in the frame (opaque and cut-out)
    StageTime transparent;     // ... the blended and transmissive ones after them, back to front
    StageTime shadows;         // the shadow map
    StageTime receivers;       // the shadows and contact darkening on the real surfaces
    // The camera image projected into the environment built from it, and that environment's
    // own maps rebuilt (EnvironmentSource::Camera*; 0 with the .hdr alone).
    StageTime environmentCapture;
    StageTime post; // lens effects (0 when off)
    // Posing animated models (poseModel) since the frame before: node animation, CPU skinning
    // and morphing, and the vertex uploads (CPU work: timed without waiting for the GPU).
    StageTime animation;
    // The share of the shadow map's texels drawn this frame: 0 when it was kept from the frame
    // before (nothing it depends on changed), 1 when drawn whole.
    double shadowMapDrawn = 0.0;
};

// Where the real environment's radiance comes from (DESIGN.md §6.5).
enum class EnvironmentSource {
    Hdr,           // the map given to setEnvironment()
    Camera,        // built from the camera frames; directions not seen yet show the camera image's mean
    CameraOverHdr, // built from the camera frames; directions not seen yet show setEnvironment()'s map
};

struct RenderOptions {
    // Multisample anti-aliasing samples per pixel (1 = off). Off by default: on llvmpipe
    // with 2 cores, 4x took the demo truck at 1280x720 from 10.5 to 28 ms per frame.
    int samples = 1;
    EnvironmentMapOptions environmentMaps;
    ShadowOptions shadows;
    // The largest side of a material texture; larger ones are scaled down when uploaded (0:
    // GL's own limit). A software rasteriser keeps every texture and its mips in memory.
    int materialTextureLimit = 0;
    LensOptions lens;
    bool profile = false;
    // The EGL display to render on: a KMS display's (KmsDisplay::eglDisplay()) to present()
    // there; null: the process' surfaceless display (headless).
    std::shared_ptr<EglDisplay> display;
};

class SceneRenderer {
public:
    // Creates the EGL display/context and framebuffers. Throws RuntimeError with a clear
    // message when no EGL or no GLES 3 context is available.
    static std::unique_ptr<SceneRenderer> create(int width, int height);
    static std::unique_ptr<SceneRenderer> create(int width, int height, const RenderOptions& options);
    virtual ~SceneRenderer() = default;

    virtual ModelId addModel(const GltfModel& model) = 0;
    // Poses a model with animations (GltfModel::rig) at `clips` for the frames that follow,
    // for every item that draws it: its transforms, skinned and morphed vertices, and the
    // bounds its culling, shadows and environment map use. No clips: the rest pose. A model
    // without animations ignores an empty call. Throws InputError for an unknown model or
    // animation.
    virtual void poseModel(ModelId model, std::span<const ClipTime> clips) = 0;
    virtual void removeModels() = 0;
    // Forgets what frames drawn so far leave to the next ones (the objects' environment maps,
    // the shadow map, the environment built from the camera), as if none had been drawn: after
    // a frame drawn only to compile the programs' variants before the camera starts.
    virtual void forgetFrames() = 0;
    // `equirect` is linear HDR radiance; `intensity` scales it.
    virtual void setEnvironment(const ImageF& equirect, float intensity) = 0;
    // Rotation from the OpenCV camera frame to the environment map's frame (+Y up), so the
    // real environment stays fixed to the world while the camera moves. Identity until set.
    // Setting it says the orientation is tracked in the next frame: only such frames add to
    // an environment built from the camera.
    virtual void setEnvironmentRotation(const glm::dmat3& environmentFromCamera) = 0;
    // The light whose shadows are drawn (with RenderOptions::shadows), environment frame. None
    // until set. Throws InputError for a zero or non-finite direction, or a negative or
    // non-finite colour or intensity.
    virtual void setLight(const DirectionalLight& light) = 0;

    // Hdr until set. A camera source projects every frame whose orientation was set into a
    // map of what the camera has seen, in radiance divided by the exposure (setExposure), and
    // lights the objects with it; setting a source forgets what was seen before.
    virtual void setEnvironmentSource(EnvironmentSource source) = 0;

    // Scales the virtual objects' radiance in the frame (not in the environment maps) before
    // tone mapping: the camera's exposure relative to the one the lighting was set up for,
    // so virtual objects darken and brighten with the camera image. 1 until set.
    virtual void setExposure(float scale) = 0;
    // The same measured for the next frame's camera image alone (not smoothed over frames),
    // which the environment built from the camera divides the image by so that what it
    // keeps stays at the reference exposure; call after setExposure(), which sets both.
    virtual void setCameraImageExposure(float scale) = 0;

    // Composites the models over `backgroundRgb` (3 channels, the output size).
    virtual void render(const Image8& backgroundRgb, const CameraIntrinsics& intrinsics,
                        std::span<const DrawItem> items) = 0;
    // The same over a camera frame in its YCbCr planes (NV12 or YUYV, the output size),
    // converted to RGB on the GPU with the frame's matrix and range.
    virtual void render(const YCbCrImage& background, const CameraIntrinsics& intrinsics,
                        std::span<const DrawItem> items) = 0;
    // Draws `overlay` (lines and text, the setup view) over the last rendered frame, after
    // compositing: readback() and present() show it. Never called, nothing is spent and the
    // frame is what render() made, bit for bit.
    virtual void drawOverlay(const OverlayScene& overlay) = 0;
    // The last rendered frame, 3 channels, row 0 at the top.
    virtual void readback(Image8& rgb) = 0;
    // Copies the last rendered frame into `window` (a surface on RenderOptions::display),
    // scaled to fit with its aspect kept, swaps and lets the window show it. Throws
    // RuntimeError.
    virtual void present(WindowTarget& window) = 0;
    [[nodiscard]] virtual RenderStats lastStats() const = 0;
    // Test access: the maps of scene object `object` (nullptr when it has none yet), and of
    // the real environment alone. Their textures stay owned by the renderer.
    [[nodiscard]] virtual const IblMaps* objectMaps(int object) const = 0;
    [[nodiscard]] virtual const IblMaps& environmentMaps() const = 0;
    // Test access: the fraction of the sphere (by solid angle) the camera source has seen; 0
    // with the .hdr source. Reads the map back from the GPU.
    [[nodiscard]] virtual double environmentCoverage() = 0;

    [[nodiscard]] virtual int width() const = 0;
    [[nodiscard]] virtual int height() const = 0;
};

} // namespace lumar
