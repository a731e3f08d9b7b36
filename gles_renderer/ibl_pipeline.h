// Builds IblMaps on the GPU: renders the mirror map face by face (the caller draws each
// face's content, the pipeline offers the real-environment skybox), then projects it to SH
// with uniformly spaced samples (sh_project + sh_reduce), renders the diffuse map from the
// SH and the two glossy maps by Phong prefiltering (phong_prefilter).
#pragma once

#include <functional>
#include <vector>

#include <glm/glm.hpp>

#include "gles_renderer/gl_object.h"
#include "gles_renderer/ibl_maps.h"

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

    // Renders the six faces of maps.mirror: binds each face with a depth buffer, clears
    // both and calls drawFace(face), then builds the mip chain. drawFace draws in the face
    // camera of cube_face_camera.h; the viewport covers the face.
    void renderMirror(IblMaps& maps, const std::function<void(int face)>& drawFace) const;

    // Draws the equirectangular real environment (linear, mipmapped 2D texture of the given
    // width) into the bound face, behind everything (no depth write).
    void drawSkybox(int face, GLuint equirect, int equirectWidth, float intensity) const;

    // Copies face `face` of `source`'s mirror map (the same size) into the bound face: the
    // real environment's own mirror map is every object map's backdrop, and a copy is
    // cheaper than drawing the skybox again.
    void copyFace(const IblMaps& source, int face) const;

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
        GlTexture samples; // RGBA32F, 1 row
        float lod = 0.0f;
    };
    Prefilter makePrefilter(float exponent, int samples, int sourceSize) const;
    void renderFaces(GLuint cube, int size, GLuint program, const std::function<void(int face)>& perFace) const;
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
    GLint prefilterEnvironmentFromFace_ = -1, prefilterLod_ = -1;
    GlTexture shSamples_; // RGBA32F: rows x (N / rows) directions
    float shLod_ = 0.0f;
    GlTexture partialSums_; // RGBA32F rows x 9
    Prefilter glossy1_;
    Prefilter glossy2_;
    GlSampler nearestLevel_;
    GlSampler nearestLevelWrapped_;
    GlFramebuffer faceFramebuffer_;  // with depth, for mirror faces
    GlFramebuffer plainFramebuffer_; // colour only, for derived maps
    GlFramebuffer readFramebuffer_;  // the source of copyFace
    GlRenderbuffer depth_;
};

} // namespace lumar
