// Builds IblMaps on the GPU: renders the mirror map face by face (the caller draws each
// face's content, the pipeline offers the real-environment skybox), then projects it to SH
// with uniformly spaced samples (sh_project + sh_reduce), renders the diffuse map from the
// SH and the two glossy maps by Phong prefiltering (phong_prefilter).
#pragma once

#include <functional>
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

    // Allocates the textures of one set (contents undefined until updated).
    [[nodiscard]] IblMaps createMaps() const;

    // Renders the six faces of maps.mirror: starts each face from `backdrop`'s mirror map
    // (the same size; the real environment's, every object map's backdrop, a copy being
    // cheaper than drawing the skybox again) or from black where it is null, clears depth,
    // calls drawFace(face), then builds the mip levels. drawFace draws in the face camera of
    // cube_face_camera.h; the viewport and the scissor box cover the face, and it must
    // leave both, the framebuffer binding and the scissor test as they are.
    //
    // The faces are drawn side by side into one 2D atlas, then copied into the cube (as are
    // the derived maps): llvmpipe rasterises what is drawn into one framebuffer as one
    // "scene", and ending one costs its worker threads a wake-up and a barrier each, which
    // for 64-px faces cost more than their pixels (38 scenes per map before, 18 now, 12 of
    // them glGenerateMipmap's). Copies between textures of one format are memcpys there,
    // and a face per 64-px tile lets both threads share the work.
    void renderMirror(IblMaps& maps, const IblMaps* backdrop, const std::function<void(int face)>& drawFace) const;

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

private:
    struct Prefilter {
        GlBuffer samples; // the LobeSamples uniform block of phong_prefilter.frag
        int count = 0;
        float lod = 0.0f;
    };
    Prefilter makePrefilter(float exponent, int samples, int sourceSize) const;
    // Draws the six size-px faces of `cube` with `program` into the derived-map atlas
    // (perFace sets per-face uniforms), then copies them into the cube's level 0.
    void renderFaces(GLuint cube, int size, GLuint program, const std::function<void(int face)>& perFace) const;
    // Where face `face`'s cell starts in an atlas (both atlases share the layout).
    [[nodiscard]] glm::ivec2 cellOrigin(int face) const;
    // Copies the size-px square at cellOrigin(face) of the atlas behind `framebuffer` into
    // level 0 of face `face` of `cube`, for every face.
    void copyAtlasToCube(GLuint framebuffer, int size, GLuint cube) const;
    // Runs `pass` with maps.mirror bound to kSourceUnit, reading the single level that
    // LINEAR_MIPMAP_NEAREST would pick at `lod`.
    void readMirrorLevel(const IblMaps& maps, float lod, const std::function<void()>& pass) const;
    // The RGBM fallback of projectSH's sums: on the CPU, over the decoded mirror map.
    void projectShOnCpu(IblMaps& maps) const;
    // Pass 1 with `program` (its source bound to kSourceUnit), then pass 2 into `coefficients`.
    void sumSamples(GLuint program, GLuint sampler, GLuint coefficients) const;

    IblSettings settings_;
    GLenum sumFormat_ = GL_RGBA32F; // partial sums and coefficients
    bool rgbm_ = false;
    int mirrorLevels_ = 1;
    std::vector<glm::vec3> shDirections_; // the SH sample set, for the CPU fallback
    GlProgram skybox_;
    GlProgram shProject_;
    GlProgram shProjectEquirect_;
    GLint equirectLod_ = -1;
    GlProgram shReduce_;
    GlProgram diffuseFromSH_;
    GlProgram phongPrefilter_;
    GLint skyboxEnvironmentFromFace_ = -1, skyboxLod_ = -1, skyboxIntensity_ = -1;
    GLint diffuseEnvironmentFromFace_ = -1;
    GLint prefilterEnvironmentFromFace_ = -1, prefilterLod_ = -1, prefilterSampleCount_ = -1;
    GlTexture shSamples_; // RGBA32F: rows x (N / rows) directions
    float shLod_ = 0.0f;
    GlTexture partialSums_; // RGBA32F rows x 9
    Prefilter glossy1_;
    Prefilter glossy2_;
    GlSampler singleLevel_;
    GlSampler nearestLevelWrapped_;
    GlFramebuffer plainFramebuffer_; // colour only: the SH sums
    GlFramebuffer readFramebuffer_;  // a cube face as a copy's source
    // Two atlases of 3 x 2 cells of max(64, largest map) px, one cell per cube face: the
    // mirror faces (with depth), and the derived maps.
    int cellSize_ = 64;
    GlTexture mirrorAtlas_;
    GlRenderbuffer mirrorAtlasDepth_;
    GlFramebuffer mirrorAtlasFramebuffer_;
    GlTexture derivedAtlas_;
    GlFramebuffer derivedAtlasFramebuffer_;
};

} // namespace lumar
