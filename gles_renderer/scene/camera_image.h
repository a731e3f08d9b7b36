// The camera image of the current frame as a small, mipmapped RGBA8 texture, for passes that
// look at the real world from elsewhere: phantoms textured by projecting the frame onto them
// inside the environment maps (DESIGN.md §6.1), and the environment built from the camera
// (§6.5). Both see it from afar (a 64-pixel cube face spans what hundreds of camera pixels
// show), so a quarter-size copy with mipmaps shows the same thing without aliasing, and costs
// one scaled blit and a mipmap build per frame instead of sampling the full frame.
#pragma once

#include <glm/glm.hpp>

#include "core/camera_model.h"
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

    [[nodiscard]] GLuint texture() const { return texture_.name(); }
    [[nodiscard]] int width() const { return width_; }
    [[nodiscard]] int height() const { return height_; }

private:
    int width_;
    int height_;
    GlTexture texture_;
    GlFramebuffer framebuffer_;
};

} // namespace lumar
