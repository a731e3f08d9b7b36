// Reading GL textures back into CPU images for the numeric tests of the environment maps.
#pragma once

#include <algorithm>
#include <utility>
#include <vector>

#include <GLES3/gl3.h>

#include "core/image.h"
#include "gles_renderer/gl/gl_object.h"
#include "gles_renderer/ibl/cube_map.h"

namespace lumar::test {

// Level `level` of a 2D float-renderable texture (RGBA16F/RGBA32F) as 3-channel floats.
inline ImageF readTexture2D(GLuint texture, int width, int height, GLenum target = GL_TEXTURE_2D, int level = 0)
{
    GlFramebuffer framebuffer = GlFramebuffer::create();
    glBindFramebuffer(GL_FRAMEBUFFER, framebuffer.name());
    glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, target, texture, level);
    std::vector<float> rgba(size_t(width) * size_t(height) * 4);
    glPixelStorei(GL_PACK_ALIGNMENT, 4);
    glReadPixels(0, 0, width, height, GL_RGBA, GL_FLOAT, rgba.data());
    ImageF image(width, height, 3);
    for (size_t i = 0; i < size_t(width) * size_t(height); ++i)
        for (size_t c = 0; c < 3; ++c)
            image.data[i * 3 + c] = rgba[i * 4 + c];
    return image;
}

// Level `level` of a cube map texture whose level 0 is `size` px a side. Row y of the image
// is GL row y (t near 0 first), as cube_map.h addresses faces.
inline CubeMapF readCube(GLuint cube, int size, int level = 0)
{
    CubeMapF out;
    out.size = std::max(1, size >> level);
    for (int face = 0; face < 6; ++face)
        out.faces[size_t(face)] =
            readTexture2D(cube, out.size, out.size, GLenum(GL_TEXTURE_CUBE_MAP_POSITIVE_X + face), level);
    return out;
}

// The same for an RGBA8 RGBM cube (shaders_es/rgbm.glsl, range 16), decoded.
inline CubeMapF readCubeRgbm(GLuint cube, int size, int level = 0)
{
    CubeMapF out;
    out.size = std::max(1, size >> level);
    GlFramebuffer framebuffer = GlFramebuffer::create();
    glBindFramebuffer(GL_FRAMEBUFFER, framebuffer.name());
    std::vector<uint8_t> rgba(size_t(out.size) * size_t(out.size) * 4);
    for (int face = 0; face < 6; ++face) {
        glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GLenum(GL_TEXTURE_CUBE_MAP_POSITIVE_X + face),
                               cube, level);
        glReadPixels(0, 0, out.size, out.size, GL_RGBA, GL_UNSIGNED_BYTE, rgba.data());
        ImageF image(out.size, out.size, 3);
        for (size_t i = 0; i < size_t(out.size) * size_t(out.size); ++i)
            for (size_t c = 0; c < 3; ++c)
                image.data[i * 3 + c] = float(rgba[i * 4 + c]) / 255.0f * float(rgba[i * 4 + 3]) / 255.0f * 16.0f;
        out.faces[size_t(face)] = std::move(image);
    }
    return out;
}

} // namespace lumar::test
