// The camera image of the current frame as a small, mipmapped RGBA8 texture, for passes that
// look at the real world from elsewhere: phantoms textured by projecting the frame onto them
// inside the environment maps (DESIGN.md §6.1), and the environment built from the camera
// (§6.5). Both see it from afar (a 64-pixel cube face spans what hundreds of camera pixels
// show), so a quarter-size copy with mipmaps shows the same thing without aliasing, and costs
// a reduction per frame (on the CPU from a frame in memory, else a scaled blit and a mipmap
// build) instead of sampling the full frame.
#pragma once

#include <vector>

#include <glm/glm.hpp>

#include "core/camera_model.h"
#include "core/image.h"
#include "gles_renderer/gl/gl_object.h"
#include "gles_renderer/gl/render_target.h"

namespace lumar {

// How a pass finds the camera image of a point it shades: the texture, and the frame camera's
// projection. A point p in the frame camera's (OpenCV) frame shows at texture coordinates
// (clipFromCamera · p).xy / w · 0.5 + 0.5 when it lies in front of the camera inside the frame.
struct CameraView {
    GLuint texture = 0; // 0: no camera image this frame
    glm::mat4 clipFromCamera{1.0f};
    // The phantoms' depth as the camera sees them (PhantomDepth), 0 when not drawn; and the
    // exposure the frame applies (SceneRenderer::setExposure): radiance = linear value / it.
    GLuint phantomDepth = 0;
    float exposure = 1.0f;
};

class CameraImage {
public:
    // Keeps the frame's size divided by `reduction` (at least 1 x 1).
    CameraImage(int frameWidth, int frameHeight, int reduction = 4);

    // Copies the camera image from `target`, where the background has just been drawn (before
    // any model), into the texture and rebuilds its mipmaps. Leaves the framebuffer bindings
    // changed.
    void capture(const RenderTarget& target);

    // The same from the frame itself (3 channels, the frame's size, row 0 at the top), on the
    // CPU: every level resampled as capture()'s linear blit and glGenerateMipmap do. On
    // llvmpipe capture() costs a wait for the rasteriser per level (each samples the one just
    // drawn), 9 a frame at 720p, which serialise the frame's start; this costs none, and
    // reduce() touches no GL, so it can run on another thread while the frame is uploaded.
    // Throws InputError when the frame's shape is not the one this image was made for.
    void reduce(const Image8& rgb);
    // Puts what reduce() computed into the texture (the context current). Best called right
    // after something that waited for the rasteriser (the renderer: the frame's upload):
    // writing a texture an earlier pass read makes llvmpipe finish everything queued first.
    void uploadReduced();

    [[nodiscard]] GLuint texture() const { return texture_.name(); }
    [[nodiscard]] int width() const { return width_; }
    [[nodiscard]] int height() const { return height_; }

private:
    int frameWidth_;
    int frameHeight_;
    int width_;
    int height_;
    int levelCount_;
    GlTexture texture_;
    GlFramebuffer framebuffer_;
    std::vector<Image8> levels_; // reduce()'s, RGBA, [0] the finest
};

} // namespace lumar
