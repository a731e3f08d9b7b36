// The real environment built from the camera (DESIGN.md §6.5): a small equirectangular map
// into which every frame's camera image is projected by the tracked orientation, each texel
// a running average of what the camera saw in its direction, in linear radiance at the
// reference exposure. Coverage grows as the camera turns; directions not seen yet are filled
// from the .hdr map or the camera image's mean (EnvironmentSource). The real environment's
// maps are then rendered from it (drawSkybox) instead of from the .hdr alone.
#pragma once

#include <glm/glm.hpp>

#include "gles_renderer/gl/gl_object.h"
#include "gles_renderer/scene/camera_image.h"

namespace lumar {

class CameraEnvironment {
public:
    // Needs a current GLES 3 context. `rgbm`: the environment maps are RGBA8 RGBM (no float
    // render targets), and so is the accumulation map. `width` x `width / 2` texels.
    CameraEnvironment(bool rgbm, int width = kDefaultWidth);

    // Forgets everything seen (a new environment, a new source).
    void reset();

    // Blends the camera image of this frame into the map: `environmentFromCamera` is the
    // camera's orientation, `exposure` the frame's exposure relative to the reference (the
    // map keeps radiance at the reference exposure). Leaves the framebuffer binding, viewport
    // and program changed.
    void accumulate(const CameraView& camera, const glm::dmat3& environmentFromCamera, float exposure);

    // Draws the map into the bound cube face (IblPipeline::renderMirror's drawFace), behind
    // everything: where not seen, `equirect` (mipmapped, `equirectWidth` texels round, its
    // intensity applied) or, when it is 0, the mean of `camera`'s image divided by `exposure`.
    void drawSkybox(int face, int faceSize, GLuint equirect, int equirectWidth, const CameraView& camera,
                    float exposure) const;

    // The fraction of the sphere (by solid angle) that the camera has seen. Reads the map
    // back: for tests and diagnostics, not for every frame.
    [[nodiscard]] double coverage() const;

    [[nodiscard]] int width() const { return width_; }
    [[nodiscard]] int height() const { return height_; }

    // 256 x 128 texels: 1.4 degrees each, four per texel of a 64-px cube face's equator.
    static constexpr int kDefaultWidth = 256;
    // A texel's running average counts at most this many frames: a new frame then still moves
    // it by 1/8, so the map follows a change in the real lighting within a second or so.
    static constexpr float kMaxWeight = 8.0f;

private:
    struct Buffer {
        GlTexture radiance; // RGBA16F linear, or RGBA8 RGBM
        GlTexture weight;   // R8: weight / kMaxWeight
        GlFramebuffer framebuffer;
    };
    Buffer makeBuffer() const;

    bool rgbm_;
    int width_;
    int height_;
    Buffer buffers_[2];
    int current_ = 0; // the buffer that holds the map; the other is the next frame's target
    GlProgram accumulate_;
    GlProgram skybox_;
    GLint accumulateCameraFromEnvironment_ = -1, accumulateClipFromCamera_ = -1, accumulateExposure_ = -1;
    GLint skyboxEnvironmentFromFace_ = -1, skyboxFillFromHdr_ = -1, skyboxEquirectLod_ = -1, skyboxCameraLod_ = -1,
          skyboxExposure_ = -1;
};

} // namespace lumar
