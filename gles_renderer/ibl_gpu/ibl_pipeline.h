// Builds IblMaps on the GPU: renders the mirror map face by face (the caller draws each
// face's content, the pipeline offers the real-environment skybox), then projects it to SH
// with uniformly spaced samples (sh_project + sh_reduce), renders the diffuse map from the
// SH and the two glossy maps by Phong prefiltering (phong_prefilter). Each step runs for
// one set, or for several slots of a bank (ibl_maps.h) in the same single pass: llvmpipe's
// cost per pass, not per texel, dominates for maps this small.
#pragma once

#include <functional>
#include <span>
#include <vector>

#include <glm/glm.hpp>

#include "gles_renderer/gl/gl_object.h"
#include "gles_renderer/ibl_gpu/ibl_maps.h"

namespace lumar {

class IblPipeline {
public:
    // Needs a current GLES 3 context. Maps are RGBA16F where the context can render to it
    // (EXT_color_buffer_float or EXT_color_buffer_half_float), RGBA8 RGBM otherwise (the SH
    // sums then run on the CPU over a read-back of the mirror map, with the same samples).
    explicit IblPipeline(const IblSettings& settings = {});

    // Whether the maps are RGBM-encoded RGBA8 (shaders must decode them).
    [[nodiscard]] bool rgbm() const { return rgbm_; }

    [[nodiscard]] const IblSettings& settings() const { return settings_; }

    // Allocates the textures of one set, or of a bank of `slots` sets (ibl_maps.h; contents
    // undefined until updated). At most maxBankSlots() slots.
    [[nodiscard]] IblMaps createMaps(int slots = 1) const;
    // The most slots a bank can have (its mirror textures stay within 2048 px, GLES 3.0's least
    // maximum texture size), at most `wanted`.
    [[nodiscard]] int maxBankSlots(int wanted) const;
    // A bank's mirror texture alone (the second of the two a bank's mirror maps are drawn
    // into in turn, so that a pass never reads the texture it draws).
    [[nodiscard]] GlTexture createMirror(int slots) const;

    // Renders the six faces of maps.mirror: starts each face from `backdrop`'s mirror map
    // (the same size; the real environment's, every object map's backdrop, a texel copy
    // being cheaper than drawing the skybox again) or from black where it is null, clears
    // depth, calls drawFace(face), then builds the mip levels. drawFace draws in the face
    // camera of cube_face_camera.h; the viewport and the scissor box cover the face, and it
    // must leave both, the framebuffer binding and the scissor test as they are.
    //
    // The faces are drawn side by side into the map's atlas (ibl_maps.h), as are the
    // derived maps: llvmpipe rasterises what is drawn into one framebuffer as one "scene",
    // and ending one costs its worker threads a wake-up and a barrier each, which for 64-px
    // faces cost more than their pixels. Nothing is copied: a copy (glCopyTexSubImage2D)
    // makes llvmpipe wait for its rasteriser threads and then copy on the calling thread,
    // where a draw is only queued, so the next scene is binned while this one rasterises.
    void renderMirror(IblMaps& maps, const IblMaps* backdrop, const std::function<void(int face)>& drawFace) const;

    // One slot of a bank's mirror pass (renderMirrorSlots).
    struct MirrorSlot {
        int slot = 0;
        // The mirror texture whose texels start the slot (0: black): a single atlas, or with
        // backdropIsBank a bank of the same layout whose same slot is copied.
        GLuint backdrop = 0;
        bool backdropIsBank = false;
        std::function<void(int face)> drawFace; // as renderMirror's; empty: the backdrop alone
    };
    // renderMirror for several slots of a bank in one pass and one mip build: every
    // backdrop, then every slot's faces.
    void renderMirrorSlots(IblMaps& bank, std::span<const MirrorSlot> slots) const;

    // Draws the equirectangular real environment (linear, mipmapped 2D texture of the given
    // width) into the bound face, behind everything (no depth write).
    void drawSkybox(int face, GLuint equirect, int equirectWidth, float intensity) const;

    // SH projection, diffuse and glossy maps from maps.mirror.
    void updateDerivedMaps(IblMaps& maps) const;
    // The same SH projection (same samples, same sums) of an equirectangular map instead of
    // the cube, into maps.coefficients: the uniform-sample method is format-independent.
    void projectEquirectSH(GLuint equirect, int equirectWidth, IblMaps& maps) const;

    // The two halves of updateDerivedMaps, for per-stage timing.
    void projectSH(IblMaps& maps) const;
    void prefilter(IblMaps& maps) const;
    // The same for the listed slots of a bank, one pass per map for all of them.
    void projectSHSlots(IblMaps& bank, std::span<const int> slots) const;
    void prefilterSlots(IblMaps& bank, std::span<const int> slots) const;
    // glossy-2 for glossy2Slots, glossy-1 (cascaded from glossy-2) for glossy1Slots, which
    // must be among them.
    void prefilterSlots(IblMaps& bank, std::span<const int> glossy2Slots, std::span<const int> glossy1Slots) const;

private:
    struct Prefilter {
        GlBuffer samples; // the LobeSamples uniform block of phong_prefilter.frag
        int count = 0;
        int levels = 1;     // the source's levels read: 0 .. levels - 1
        GLuint program = 0; // phongPrefilter_ or phongPrefilterLevels_, and its uniforms
        GLint environmentFromFace = -1, atlasSize = -1, slot = -1, sampleCount = -1;
    };
    // Samples (direction, weight) and their levels (level, clamp) into a LobeSamples block.
    static Prefilter uploadPrefilter(const std::vector<glm::vec4>& samples, const std::vector<glm::vec2>& levels);
    // glossy-2's: importance-sampled, from the mirror's levels (of sourceLevels at most).
    Prefilter makeLobePrefilter(float exponent, int count, int sourceLevels) const;
    // glossy-1's cascade: equal-solid-angle samples weighted by the lobe, from the single
    // level of sourceSize-px faces.
    Prefilter makeCapPrefilter(float exponent, int count, int sourceSize) const;
    // Draws the six size-px faces of each listed slot of the cube atlas bank `atlas` with
    // `program` (perFace sets per-face uniforms).
    void renderFaces(GLuint atlas, int size, std::span<const int> slots, GLuint program,
                     const std::function<void(int slot, int face)>& perFace) const;
    // The mirror level that LINEAR_MIPMAP_NEAREST would pick at `lod`.
    [[nodiscard]] int mirrorLevel(float lod) const;
    // The size of that level of a mirror bank of `slots` atlases.
    [[nodiscard]] glm::vec2 mirrorLevelSize(int level, int slots = 1) const;
    // Runs `pass` with maps.mirror bound to kSourceUnit, reading the single level
    // mirrorLevel(lod) (its faces mirrorSize >> level px).
    void readMirrorLevel(const IblMaps& maps, float lod, const std::function<void()>& pass) const;
    // The RGBM fallback of projectSH's sums: on the CPU, over the decoded mirror map.
    void projectShOnCpu(IblMaps& maps, int slot) const;
    // Pass 1 with `program` (its source bound to kSourceUnit; perSlot sets the slot's
    // uniforms), then pass 2 into `coefficients`, for slots 0..slots-1 (at least one).
    void sumSamples(GLuint program, GLuint sampler, GLuint coefficients, std::span<const int> slots,
                    const std::function<void(int slot)>& perSlot) const;
    // Grows the buffers shared by all sets to a bank of `slots` (partial sums, mirror depth).
    void reserveSlots(int slots) const;

    IblSettings settings_;
    GLenum sumFormat_ = GL_RGBA32F; // partial sums and coefficients
    bool rgbm_ = false;
    int mirrorLevels_ = 1;
    std::vector<glm::vec3> shDirections_; // the SH sample set, for the CPU fallback
    GlProgram skybox_;
    GlProgram atlasCopy_; // a backdrop's texels into a mirror atlas
    GlProgram shProject_;
    GlProgram shProjectEquirect_;
    GLint equirectLod_ = -1;
    GlProgram shReduce_;
    GlProgram diffuseFromSH_;
    GlProgram phongPrefilter_;       // one source level (glossy-1's cascade)
    GlProgram phongPrefilterLevels_; // a level per sample (glossy-2, SAMPLE_LEVELS)
    GLint skyboxEnvironmentFromFace_ = -1, skyboxLod_ = -1, skyboxIntensity_ = -1;
    GLint diffuseEnvironmentFromFace_ = -1;
    GLint diffuseSlot_ = -1, shProjectSlot_ = -1, shProjectCellOrigin_ = -1;
    GLint shProjectAtlasSize_ = -1, atlasCopyOffset_ = -1;
    GlTexture shSamples_; // RGBA32F: rows x (N / rows) directions
    float shLod_ = 0.0f;
    mutable GlTexture partialSums_; // RGBA32F 2D array: 3 layers of (rows x slots) x 3
    mutable int reservedSlots_ = 0;
    Prefilter glossy1_;
    Prefilter glossy2_;
    GlSampler singleLevel_;
    GlSampler nearestLevel_;
    GlSampler nearestLevelWrapped_;
    GlFramebuffer plainFramebuffer_;       // colour only: the SH coefficients
    GlFramebuffer partialSumsFramebuffer_; // the partial sums' layers, one attachment each
    GlFramebuffer readFramebuffer_;        // the mirror atlas, read back (RGBM)
    // Framebuffers the maps' atlases are attached to in turn: the mirror maps' (with a
    // depth buffer shared by all of them) and the derived maps'.
    mutable GlRenderbuffer mirrorAtlasDepth_;
    GlFramebuffer mirrorAtlasFramebuffer_;
    GlFramebuffer derivedAtlasFramebuffer_;
};

} // namespace lumar
