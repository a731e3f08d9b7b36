#include "gles_renderer/gl/gpu_texture.h"

#include <algorithm>
#include <bit>

namespace lumar {

int mipLevelCount(int width, int height)
{
    return std::bit_width(unsigned(std::max({width, height, 1})));
}

GlTexture uploadMaterialTexture(const Image8& rgba, bool srgb)
{
    GlTexture texture = GlTexture::create();
    glBindTexture(GL_TEXTURE_2D, texture.name());
    glTexStorage2D(GL_TEXTURE_2D, mipLevelCount(rgba.width, rgba.height), srgb ? GL_SRGB8_ALPHA8 : GL_RGBA8, rgba.width,
                   rgba.height);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
    glTexSubImage2D(GL_TEXTURE_2D, 0, 0, 0, rgba.width, rgba.height, GL_RGBA, GL_UNSIGNED_BYTE, rgba.data.data());
    glGenerateMipmap(GL_TEXTURE_2D);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR_MIPMAP_LINEAR);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_REPEAT);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_REPEAT);
    return texture;
}

GlTexture makeSolidTexture(uint8_t r, uint8_t g, uint8_t b, uint8_t a)
{
    const uint8_t texel[4] = {r, g, b, a};
    GlTexture texture = GlTexture::create();
    glBindTexture(GL_TEXTURE_2D, texture.name());
    glTexStorage2D(GL_TEXTURE_2D, 1, GL_RGBA8, 1, 1);
    glTexSubImage2D(GL_TEXTURE_2D, 0, 0, 0, 1, 1, GL_RGBA, GL_UNSIGNED_BYTE, texel);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    return texture;
}

GlTexture makeDepthCompareTexture(int width, int height)
{
    GlTexture texture = GlTexture::create();
    glBindTexture(GL_TEXTURE_2D, texture.name());
    glTexStorage2D(GL_TEXTURE_2D, 1, GL_DEPTH_COMPONENT24, width, height);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_COMPARE_MODE, GL_COMPARE_REF_TO_TEXTURE);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_COMPARE_FUNC, GL_LEQUAL);
    return texture;
}

} // namespace lumar
