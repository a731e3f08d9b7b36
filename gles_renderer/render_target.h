// The offscreen framebuffer the scene is drawn into: RGBA8 colour + 24-bit depth, optionally
// multisampled with a blit resolve into a single-sampled framebuffer for readback.
#pragma once

#include "gles_renderer/gl_object.h"

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
    // The single-sampled framebuffer holding the finished frame.
    [[nodiscard]] GLuint readFramebuffer() const;

    [[nodiscard]] int width() const { return width_; }
    [[nodiscard]] int height() const { return height_; }
    [[nodiscard]] int samples() const { return samples_; }

private:
    int width_;
    int height_;
    int samples_;
    GlRenderbuffer colour_;
    GlRenderbuffer depth_;
    GlFramebuffer drawFramebuffer_;
    // Only when multisampled.
    GlRenderbuffer resolvedColour_;
    GlFramebuffer resolvedFramebuffer_;
};

} // namespace lumar
