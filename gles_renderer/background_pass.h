// Pass 1 of a frame: the camera image copied into the whole framebuffer, bit-exact. A
// single-sampled target gets it uploaded straight into its colour texture (no draw at all);
// a multisampled one gets it drawn by a fullscreen triangle from a persistent texture.
#pragma once

#include "core/image.h"
#include "gles_renderer/gl_object.h"
#include "gles_renderer/render_target.h"

namespace lumar {

class BackgroundPass {
public:
    // The texture unit the camera image is bound to while drawing.
    static constexpr GLuint kTextureUnit = 5;

    // `target` must outlive the pass.
    explicit BackgroundPass(const RenderTarget& target);

    // Puts `rgb` (3 channels, the target's size, row 0 at the top) into every pixel of the
    // target, which must be bound for drawing. Throws InputError when the shape differs.
    void draw(const Image8& rgb) const;

private:
    void upload(GLuint texture, const Image8& rgb) const;

    int width_;
    int height_;
    GLuint targetTexture_; // the target's colour texture; 0 when multisampled
    // Only for multisampled targets:
    GlProgram program_;
    GlTexture texture_;
    GlVertexArray emptyVertexArray_; // GLES 3 draws need a bound vertex array
};

} // namespace lumar
