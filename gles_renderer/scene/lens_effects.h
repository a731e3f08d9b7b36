// Lens effects on the virtual objects' light (DESIGN.md §6.5): bloom and glare streaks from
// what is bright in the virtual contribution, added onto the frame.
//
// The part of the objects' linear radiance (times the exposure) above the threshold is drawn
// beside the frame's colour into a second attachment of the frame's framebuffer (mesh.frag's
// fragRadiance): R11F_G11F_B10F or RGBA16F where they render, else RGBA8 RGBM like the
// environment maps. A pyramid of 2 x 2 box downsamples (half size first) holds that bright
// light; the bloom climbs back up it, every level bilinearly doubled and mixed with the next
// finer one so each level has an equal share; the glare streaks gather the eighth-size level
// along the configured rays. Both conserve the bright light's energy (sum of radiance x area),
// scaled by their intensities, and are added to the frame in linear light
// (lens_composite.frag), which leaves every pixel they do not reach exactly as it was.
//
// Whole (LensCulling; a GPU's choice): every step is a GL pass over whole images. Culled (a
// software rasteriser's): the radiance under the objects is read back and halved on the CPU
// (or, where it does not read back as stored, drawn there by a bright pass and read), the
// pyramid and the glare are computed on the CPU within reach of its lit texels
// (lens_cpu_passes.h), and the composite is drawn only in the tiles where they add light,
// reading the frame where it draws (framebuffer fetch). The car scene with bloom on llvmpipe:
// lens effects 12.3 -> 5.2 ms of CPU a frame (1e66675 -> this), 27.7 ms before dce723b.
#pragma once

#include <functional>
#include <span>
#include <vector>

#include <glm/glm.hpp>

#include "core/helper_thread.h"
#include "core/image.h"
#include "gles_renderer/gl/gl_object.h"
#include "gles_renderer/gl/render_target.h"
#include "gles_renderer/scene/gpu_model.h"
#include "gles_renderer/scene/lens_cpu_passes.h"
#include "gles_renderer/scene/pixel_rects.h"
#include "gles_renderer/scene/scene_renderer.h"

namespace lumar {

class LensEffects {
public:
    // Needs a current GLES 3 context; attaches its radiance image to `target`'s framebuffer,
    // where it stays inert until beginVirtual(). `rgbm`: no float format renders, every image
    // is RGBA8 RGBM (the radiance too, as mesh.frag writes it where the maps are RGBM).
    // Throws InputError for options out of range.
    LensEffects(const RenderTarget& target, const LensOptions& options, bool rgbm);

    LensEffects(const LensEffects&) = delete;
    LensEffects& operator=(const LensEffects&) = delete;

    // Around the virtual objects' draw in the frame (the target bound): beginVirtual() clears
    // the radiance image and lets fragment output 1 write to it, endVirtual() stops that.
    void beginVirtual() const;
    void endVirtual() const;
    // Between beginVirtual() and endVirtual(), around BLEND primitives blended into the frame
    // (MeshPass::onBlending). A float radiance image is blended like the frame (alpha is the
    // coverage). An RGBM one cannot be: its alpha is the encoding's scale, and blending would
    // weigh the colours by the scale and keep the one behind, so it is left out while
    // `blending`: what lies behind a BLEND surface keeps its light, and the surface adds none
    // to the bloom and glare (on float images it adds its share and dims what is behind).
    void blendingVirtual(bool blending) const;
    // Where this frame's virtual light can be and where its effects can reach, window pixels.
    struct Area {
        PixelRect reach;                // the pixels the effects can change: the sources grown by the reach
        std::vector<PixelRect> sources; // disjoint: the virtual objects' (not the phantoms') projected bounds
    };
    // Both empty without virtual objects.
    [[nodiscard]] Area area(std::span<const GpuModel> models, std::span<const DrawItem> items,
                            const glm::mat4& clipFromCamera) const;
    // Culled: the CPU's share of the effects (the pyramid, the glare) split in two bands of
    // rows, one on `helper` (null: all on the calling thread). The rasteriser has nothing
    // queued while they run: on a two-core llvmpipe one core idled through ~0.85 ms a frame.
    void useHelper(HelperThread* helper) { helper_ = helper; }
    // Adds the effects onto the target's colour within `area.reach`; nothing at all when it
    // is empty. Leaves the target bound for drawing.
    void apply(const RenderTarget& target, const Area& area);
    // The same for virtual light anywhere within `reach`.
    void apply(const RenderTarget& target, const PixelRect& reach) { apply(target, Area{reach, {reach}}); }

    // Test access. The radiance image the objects are drawn into (the frame's size).
    [[nodiscard]] GLuint radianceTexture() const { return radiance_.name(); }
    // The bright light above the threshold, the bloom and the glare as last computed, linear,
    // decoded from RGBM; each at its own size (half, half and an eighth of the frame's). Where
    // culling left texels undrawn they read 0: what the composite takes them for.
    [[nodiscard]] ImageF readBright() const;
    [[nodiscard]] ImageF readBloom() const;
    [[nodiscard]] ImageF readGlare() const;
    [[nodiscard]] bool radianceRgbm() const { return radianceRgbm_; }
    // Its internal format: RGBA8 (RGBM), R11F_G11F_B10F or RGBA16F.
    [[nodiscard]] GLenum radianceFormat() const { return radianceFormat_; }
    // Light above it feeds the effects: mesh.frag writes only that part into the radiance
    // image (FrameUniforms::lensParams).
    [[nodiscard]] float threshold() const { return options_.threshold; }
    [[nodiscard]] bool rgbm() const { return rgbm_; } // the pyramid's
    [[nodiscard]] bool culled() const { return culled_; }
    // The composite reads the frame's pixels where it draws them (framebuffer fetch), not
    // from a copy of the frame.
    [[nodiscard]] bool fetchesFrame() const { return fetch_; }

private:
    struct Level {
        int width = 0;
        int height = 0;
        GlTexture texture;
        GlFramebuffer framebuffer;
    };
    Level makeLevel(int width, int height) const;
    void drawInto(Level& level, const PixelRect& texels);
    // The GL passes over every texel (LensCulling::Whole).
    void applyWhole(const RenderTarget& target, const PixelRect& reach);
    // The bright pass over the sources, read back; the rest on the CPU within reach of its
    // light (lens_cpu_passes.h), the composite in the tiles it reaches (LensCulling::Culled).
    void applyCulled(const RenderTarget& target, const Area& area);
    // Culled, readsRadiance_: the radiance under `sourceBounds` read back and halved (2 x 2
    // means) into cpuLevels_[0].
    void readRadianceHalved(const PixelRect& sourceBounds);
    // A level's `texels` read back, linear (RGBM decoded), into `region` (reset over them);
    // `bytes` holds what glReadPixels gives.
    void readLevel(const Level& level, const PixelRect& texels, RadianceRegion& region,
                   std::vector<uint8_t>& bytes) const;
    // Culled: the frame's tiles within reach of a texel of the bright image that holds light,
    // as disjoint rectangles within `area`.
    [[nodiscard]] std::vector<PixelRect> litTiles(const PixelRect& area) const;
    // Culled: the tiles of `candidates` (litTiles) where the bloom and the glare computed on
    // the CPU add light the composite keeps.
    [[nodiscard]] std::vector<PixelRect> reachedTiles(std::span<const PixelRect> candidates) const;
    // Culled: what the bloom's level `level` (below its coarsest) is doubled from, the level
    // above going down or, above that, coming up; and the bloom itself.
    [[nodiscard]] const RadianceRegion& cpuCoarser(int level) const;
    [[nodiscard]] const RadianceRegion& cpuBloom() const;
    // How far from a bright pixel the bloom and the glare reach, in pixels.
    [[nodiscard]] int reachPixels() const;
    [[nodiscard]] ImageF read(const Level& level) const;
    void copyFrame(const RenderTarget& target, const PixelRect& area);
    // Adds the effects onto the target within `tiles` (the composite), reading the bloom and
    // the glare from these textures.
    void composite(const RenderTarget& target, std::span<const PixelRect> tiles, const PixelRect& bounds, GLuint bloom,
                   GLuint glare);
    // `work` over `texels`: two bands of rows, one on helper_, where there is one and enough rows.
    void inBands(const PixelRect& texels, const std::function<void(const PixelRect&)>& work) const;

    LensOptions options_;
    HelperThread* helper_ = nullptr;
    bool radianceRgbm_;
    GLenum radianceFormat_ = GL_RGBA16F;
    bool rgbm_;
    bool culled_;                // LensCulling, decided
    bool fetch_;                 // GL_EXT_shader_framebuffer_fetch on a single-sampled target
    bool readsRadiance_ = false; // culled: the bright image from the radiance read back, no bright pass
    int width_;
    int height_;
    int samples_;
    GlTexture radiance_;                  // single-sampled, read by the bright pass
    GlRenderbuffer multisampledRadiance_; // drawn into when the target is multisampled
    GlFramebuffer radianceFramebuffer_;   // radiance_ alone: resolved into (multisampled), read back
    GLuint targetFramebuffer_;
    std::vector<glm::ivec2> levelSizes_; // the pyramid's, [0]: half the frame's size
    int bloomLevels_ = 0;
    bool glare_ = false;
    std::vector<glm::vec2> glareSteps_; // per streak: one sample's offset, glare texels
    std::vector<float> glareWeights_;   // by sample index, over all streaks summing to 1
    // Whole: the pyramid on GL. Culled: down_[0] alone (the bright pass's image).
    std::vector<Level> down_; // [0]: half size, thresholded
    std::vector<Level> up_;   // up_[k]: the bloom from level k down (up_.back() unused)
    Level glareLevel_;
    // Culled: the pyramid on the CPU and the results uploaded for the composite (RGB16F).
    std::vector<RadianceRegion> cpuLevels_; // [0]: the bright image, read back
    std::vector<RadianceRegion> cpuUp_;
    RadianceRegion cpuGlare_;
    std::vector<uint8_t> brightBytes_;     // the bright image's texels as read back
    std::vector<uint32_t> packedRadiance_; // readsRadiance_: the radiance's R11F_G11F_B10F texels
    GlTexture bloomUpload_;
    GlTexture glareUpload_;
    Level frameCopy_;        // RGBA8 copy of the frame, read by the composite (without fetch_)
    GlProgram downsample_;   // a step down the pyramid
    GlProgram brightPass_;   // its first step, where the radiance's format is not the pyramid's
    GlProgram upsample_;     // whole, with the bloom only
    GlProgram glareProgram_; // whole, with the glare only
    GlProgram composite_;
};

} // namespace lumar
