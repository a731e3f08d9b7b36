// Pass 1 of a frame: the camera image copied into the whole framebuffer, bit-exact.
#pragma once

#include "core/image.h"
#include "gles_renderer/gl_object.h"

namespace lumar {

class BackgroundPass {
public:
    // The texture unit the camera image is bound to while drawing.
    static constexpr GLuint kTextureUnit = 5;

    BackgroundPass(int width, int height);

    // Uploads `rgb` (3 channels, the pass' size, row 0 at the top) into the persistent
    // texture and draws it over the bound framebuffer with depth testing off. Throws
    // InputError when the image's shape differs.
    void draw(const Image8& rgb) const;

private:
    int width_;
    int height_;
    GlProgram program_;
    GlTexture texture_;
    GlVertexArray emptyVertexArray_;  // GLES 3 draws need a bound vertex array
};

} // namespace lumar
