// The models, depth-tested and shaded by mesh.vert / mesh.frag with each item's own four
// environment maps: pass 2 of a frame, and the other objects inside a cube-map face.
//
// Forward, not deferred. llvmpipe shades a 4 x 4 block once for every triangle that touches
// it, so most of the car's shading scales with its triangles' edges, not its pixels (car.toml,
// shading CPU above a constant-colour shader's: 9.6, 23.5 and 63 ms at 640x360, 1280x720 and
// 2560x1440, which fit ~60 % edges at 1280x720). Deferred shading was measured (a surface
// buffer of position, normal, tangent and uvs, then one stencil-tested pass per material over
// its screen bounds) and lost: writing the buffer alone cost 10.7-14 ms against 6 ms for a
// constant-colour forward pass, the materials' passes 16.5 ms, 28.5 ms in all against 25.7
// forward, and 64 MB more resident.
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <map>
#include <span>
#include <utility>
#include <vector>

#include "gles_renderer/gl/gl_object.h"
#include "gles_renderer/ibl_gpu/ibl_maps.h"
#include "gles_renderer/scene/gpu_model.h"
#include "gles_renderer/scene/scene_renderer.h"
#include "gles_renderer/scene/uniform_blocks.h"

namespace lumar {

class StateCache;

class MeshPass {
public:
    // Texture units of the material maps and the environment map.
    static constexpr GLuint kBaseColorUnit = 0;
    static constexpr GLuint kMetallicRoughnessUnit = 1;
    static constexpr GLuint kNormalUnit = 2;
    static constexpr GLuint kEmissiveUnit = 3;
    static constexpr GLuint kSpecularUnit = 4;
    static constexpr GLuint kLobeUnit = 5;
    static constexpr GLuint kTangentRotationUnit = 6;
    static constexpr GLuint kDiffuseMapUnit = 7;
    static constexpr GLuint kGlossy1MapUnit = 8;
    static constexpr GLuint kGlossy2MapUnit = 9;
    static constexpr GLuint kMirrorMapUnit = 10;
    static constexpr GLuint kShadowMapUnit = 11; // the dominant light's (ShadowPass)
    // phantom.frag's camera image and the phantoms' depth as the frame camera sees them.
    static constexpr GLuint kCameraImageUnit = 12;
    static constexpr GLuint kCameraDepthUnit = 13;
    static constexpr GLuint kOcclusionUnit = 14;    // glTF occlusionTexture (linear r)
    static constexpr GLuint kTransmissionUnit = 15; // KHR_materials_transmission's texture (linear r)

    // How phantoms show the camera image in a view that is not the frame camera's (an
    // environment map's cube face): phantom.frag projects each fragment into the image.
    struct PhantomCamera {
        glm::mat4 frameCameraFromView{1.0f}; // the view's camera frame to the frame camera's
        glm::mat4 clipFromFrameCamera{1.0f}; // the frame camera's projection
        float exposure = 1.0f;               // camera radiance = linear camera value / exposure
        GLuint image = 0;                    // CameraImage::texture()
        GLuint depth = 0;                    // PhantomDepth::texture()
    };

    MeshPass();

    // Draws `items` into the bound framebuffer (which must have been cleared of depth),
    // item i lit by maps[i]. Every item's model id must index `models` (the caller checks).
    // `skip`: an item index not to draw (an environment map's owner), or -1.
    // `phantoms`: Shaded draws phantom items like the rest (environment maps); DepthOnly
    // draws them first into depth alone (the frame: the camera image shows them); Skip leaves
    // them out (the frame with shadows: ShadowPass::drawReceivers drew them). Receiver-only
    // items (DrawItem::receiverOnly) are never drawn here.
    // `camera` (with Phantoms::Shaded): phantoms are drawn by phantom.frag, carrying the
    // camera image where the camera saw them, after the other items; null: by mesh.frag.
    // `detail`: Full meshes (the frame) or their simplified Proxy stand-ins (environment maps),
    // each item's level chosen by proxyLevelFor from its size in pixels: `focalPixels` is
    // the view's focal length in pixels (<= 0: unknown, the finest levels).
    enum class Phantoms { Shaded, DepthOnly, Skip };
    enum class Detail { Full, Proxy };
    void draw(const FrameUniforms& frame, const std::vector<GpuModel>& models, std::span<const DrawItem> items,
              std::span<const IblMaps* const> maps, int skip = -1, Phantoms phantoms = Phantoms::Shaded,
              Detail detail = Detail::Full, double focalPixels = 0.0, const PhantomCamera* camera = nullptr) const;

    // Called by every draw() once the opaque items are drawn, before the blended and
    // transmissive ones (the renderer's `transparent` stage starts there); empty: nothing.
    void onTransparentStart(std::function<void()> hook) { transparentStart_ = std::move(hook); }
    // Called with true before BLEND primitives are blended into the target and with false
    // after (the lens effects' RGBM radiance image is left out of blending: lens_effects.h).
    void onBlending(std::function<void(bool)> hook) { blendingHook_ = std::move(hook); }

    // How many pixels the longest side of `item`'s model spans, seen at its bounding-box
    // centre's distance with focal length `focalPixels`; infinite where the camera is inside
    // its bounding sphere.
    static double modelPixels(const DrawItem& item, const GpuModel& model, double focalPixels);

    // The depth texture the mesh program's shadow lookups read (bound at kShadowMapUnit by
    // every draw; FrameUniforms says whether to read it). Owned by the caller.
    void setShadowMap(GLuint texture) { shadowMap_ = texture; }

    // mesh.frag linked for one combination of mesh_feature bits (mesh_features.h).
    struct Variant {
        GlProgram program;
        GLint cameraFromMeshLocation = -1;
        GLint normalFromMeshLocation = -1;
        GLint mapSlotLocation = -1; // uMapSlot: the environment maps' slot in their bank
    };

    // How many variants are linked (each ~1 MB resident on llvmpipe).
    [[nodiscard]] size_t linkedVariants() const { return variants_.size(); }

private:
    // The variant for `features`, linked on first use.
    const Variant& variant(uint32_t features) const;

    // A primitive with alphaMode BLEND or a transmissive material, held back to be drawn
    // after the opaque ones.
    struct BlendedPrimitive {
        double depth; // of its bounding-box centre along the view: drawn farthest first
        size_t item;
        const GpuPrimitive* primitive;
    };

    // With `variants`, mesh.frag's variant for each primitive's material and the view
    // (viewFeatures_), switching programs as needed; else the bound program, whose locations
    // are given: normalFromMeshLocation < 0 is the depth-only program (no normals, no materials).
    // `blended`: where BLEND primitives go instead of being drawn (null: drawn in order).
    void drawItem(const DrawItem& item, const IblMaps* maps, const std::vector<GpuModel>& models, StateCache& state,
                  GLint cameraFromMeshLocation, GLint normalFromMeshLocation, Detail detail, double focalPixels,
                  std::vector<BlendedPrimitive>* blended = nullptr, size_t itemIndex = 0, bool variants = false) const;
    void drawPrimitive(const DrawItem& item, const GpuModel& model, const GpuPrimitive& primitive, StateCache& state,
                       GLint cameraFromMeshLocation, GLint normalFromMeshLocation, bool variants = false) const;
    // The held-back BLEND primitives, back to front, blended over what is drawn, depth-tested
    // without depth writes. `canBlend` false (RGBM environment maps, whose alpha is the
    // encoding's scale): drawn as cut-outs at alpha 0.5 by the shader, with depth writes.
    void drawBlended(std::span<const DrawItem> items, std::span<const IblMaps* const> maps,
                     const std::vector<GpuModel>& models, StateCache& state, bool canBlend) const;

    // The phantoms among `items` with phantom.frag.
    void drawCameraPhantoms(const PhantomCamera& camera, const std::vector<GpuModel>& models,
                            std::span<const DrawItem> items, std::span<const IblMaps* const> maps, int skip,
                            StateCache& state, Detail detail, double focalPixels) const;

    // Depth along the view of the item's bounding-box centre (draw order).
    static double centreDepth(const DrawItem& item, const std::vector<GpuModel>& models);

    mutable std::vector<std::pair<double, size_t>> order_; // per-draw scratch
    mutable std::vector<BlendedPrimitive> blended_;        // per-draw scratch
    // Linked as draws need them: one per combination of features a scene's materials and
    // views use.
    mutable std::map<uint32_t, Variant> variants_;
    mutable uint32_t viewFeatures_ = 0; // of the view being drawn
    GlProgram phantomProgram_;
    GLint phantomCameraFromMeshLocation_;
    GLint phantomNormalFromMeshLocation_;
    GLint phantomFrameCameraFromViewLocation_;
    GLint phantomClipFromFrameCameraLocation_;
    GLint phantomInverseExposureLocation_;
    GlProgram depthOnly_;
    GLint depthOnlyCameraFromMeshLocation_;
    GlBuffer frameUniforms_;
    // Bound to the environment maps' units while the pass draws: every lookup of the maps
    // reads level 0 (textureLod 0, magnified), which a mipmapped map's own LINEAR_MIPMAP_LINEAR
    // filter reads too, but llvmpipe then builds the level selection into every lookup.
    GlSampler levelZero_;
    GLuint shadowMap_ = 0;
    std::function<void()> transparentStart_;
    std::function<void(bool)> blendingHook_;
};

} // namespace lumar
