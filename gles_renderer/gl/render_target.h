// The offscreen framebuffer the scene is drawn into: 8-bit colour + 24-bit depth. Single-
// sampled, the colour is an RGBA8 texture the camera image can be uploaded into directly;
// multisampled, RGBA8 renderbuffers resolved by a blit into a single-sampled one for readback.
#pragma once

#include "gles_renderer/gl/gl_object.h"

namespace lumar {

class RenderTarget {
public:
    // samples <= 1: no multisampling. More than GL_MAX_SAMPLES is reduced to it (logged).
    // Throws RuntimeError when GL cannot make a complete framebuffer of this size.
    RenderTarget(int width, int height, int samples);

    // Binds the framebuffer to draw into and sets the viewport to cover it.
    void bindForDrawing() const;
    // Makes the finished frame readable from readFramebuffer(): resolves the samples (if
    // any) and discards the depth buffer, which no later step reads.
    void finishFrame() const;
    // Mid-frame: copies what has been drawn so far into readFramebuffer() (a resolve when
    // multisampled; nothing to do otherwise), keeping the depth buffer.
    void resolveColour() const;
    // The single-sampled framebuffer holding the finished frame.
    [[nodiscard]] GLuint readFramebuffer() const;
    // The framebuffer drawn into (multisampled where the target is), for passes that attach
    // more images to it (gles_renderer/scene/lens_effects.h).
    [[nodiscard]] GLuint drawFramebuffer() const { return drawFramebuffer_.name(); }
    // The RGBA8 colour texture drawn into, or 0 when multisampled.
    [[nodiscard]] GLuint colourTexture() const { return colourTexture_.name(); }

    [[nodiscard]] int width() const { return width_; }
    [[nodiscard]] int height() const { return height_; }
    [[nodiscard]] int samples() const { return samples_; }

private:
    int width_;
    int height_;
    int samples_;
    GlTexture colourTexture_; // single-sampled
    GlRenderbuffer colour_;   // multisampled
    GlRenderbuffer depth_;
    GlFramebuffer drawFramebuffer_;
    // Only when multisampled.
    GlRenderbuffer resolvedColour_;
    GlFramebuffer resolvedFramebuffer_;
};

} // namespace lumar
