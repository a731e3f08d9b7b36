// Reading GL textures back into CPU images for the numeric tests of the environment maps.
#pragma once

#include <algorithm>
#include <utility>
#include <vector>

#include <GLES3/gl3.h>

#include "core/image.h"
#include "gles_renderer/gl/gl_object.h"
#include "gles_renderer/ibl/cube_map.h"
#include "gles_renderer/ibl_gpu/ibl_maps.h"

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

// Level `level` of a cube map held as a 2D atlas (gles_renderer/ibl_gpu/ibl_maps.h) whose
// faces are `size` px a side at level 0: each face read from its cell. Row y of a face is GL
// row y (t near 0 first), as cube_map.h addresses faces.
// `slot` of a bank of `slots` atlases (ibl_maps.h): the atlas from row slot x its height.
inline CubeMapF readCubeAtlas(GLuint atlas, int size, int level = 0, int slot = 0, int slots = 1)
{
    CubeMapF out;
    out.size = std::max(1, size >> level);
    const glm::ivec2 extent = glm::max(cubeAtlasSize(size) >> level, glm::ivec2(1));
    const ImageF whole = readTexture2D(atlas, extent.x, extent.y * slots, GL_TEXTURE_2D, level);
    for (int face = 0; face < 6; ++face) {
        const glm::ivec2 origin = (cubeAtlasCellOrigin(face, size) >> level) + glm::ivec2(0, slot * extent.y);
        ImageF image(out.size, out.size, 3);
        for (int y = 0; y < out.size; ++y)
            for (int x = 0; x < out.size; ++x)
                std::copy_n(whole.at(origin.x + x, origin.y + y), 3, image.at(x, y));
        out.faces[size_t(face)] = std::move(image);
    }
    return out;
}

// The mirror map of a set, or of a bank's slot (IblMaps::textures()).
inline CubeMapF readMirrorMap(const IblMaps& maps, int size)
{
    const IblTextures t = maps.textures();
    return readCubeAtlas(t.mirror, size, 0, t.slot, t.slots);
}

// The same for an RGBA8 RGBM atlas (shaders_es/rgbm.glsl, range 16), decoded.
inline CubeMapF readCubeAtlasRgbm(GLuint atlas, int size, int level = 0, int slot = 0, int slots = 1)
{
    CubeMapF out;
    out.size = std::max(1, size >> level);
    const glm::ivec2 extent = glm::max(cubeAtlasSize(size) >> level, glm::ivec2(1));
    const int width = extent.x, height = extent.y * slots;
    GlFramebuffer framebuffer = GlFramebuffer::create();
    glBindFramebuffer(GL_FRAMEBUFFER, framebuffer.name());
    glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, atlas, level);
    std::vector<uint8_t> rgba(size_t(width) * size_t(height) * 4);
    glPixelStorei(GL_PACK_ALIGNMENT, 4);
    glReadPixels(0, 0, width, height, GL_RGBA, GL_UNSIGNED_BYTE, rgba.data());
    for (int face = 0; face < 6; ++face) {
        const glm::ivec2 origin = (cubeAtlasCellOrigin(face, size) >> level) + glm::ivec2(0, slot * extent.y);
        ImageF image(out.size, out.size, 3);
        for (int y = 0; y < out.size; ++y)
            for (int x = 0; x < out.size; ++x) {
                const uint8_t* t = &rgba[(size_t(origin.y + y) * size_t(width) + size_t(origin.x + x)) * 4];
                for (int c = 0; c < 3; ++c)
                    image.at(x, y)[c] = float(t[c]) / 255.0f * float(t[3]) / 255.0f * 16.0f;
            }
        out.faces[size_t(face)] = std::move(image);
    }
    return out;
}

} // namespace lumar::test
