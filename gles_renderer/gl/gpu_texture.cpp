#include "gles_renderer/gl/gpu_texture.h"

#include <algorithm>
#include <bit>
#include <cmath>

#include <stb_image_resize.h>

#include "core/error.h"

namespace lumar {

int mipLevelCount(int width, int height)
{
    return std::bit_width(unsigned(std::max({width, height, 1})));
}

std::pair<int, int> cappedTextureSize(int width, int height, int maxSize)
{
    const int larger = std::max(width, height);
    if (maxSize <= 0 || larger <= maxSize)
        return {width, height};
    const double scale = double(maxSize) / double(larger);
    const auto side = [&](int n) { return std::clamp(int(std::lround(double(n) * scale)), 1, maxSize); };
    return {side(width), side(height)};
}

Image8 downscaleTexture(const Image8& rgba, int width, int height, bool srgb)
{
    Image8 out(width, height, 4);
    // stb's default downsampling filter (Mitchell) over the wrapped edges the sampler repeats;
    // sRGB colour is filtered in linear light and weighted by alpha, data maps (normals,
    // metallic-roughness) channel by channel as stored.
    const int ok = stbir_resize_uint8_generic(
        rgba.data.data(), rgba.width, rgba.height, rgba.width * 4, out.data.data(), width, height, width * 4, 4,
        srgb ? 3 : STBIR_ALPHA_CHANNEL_NONE, 0, STBIR_EDGE_WRAP, STBIR_FILTER_DEFAULT,
        srgb ? STBIR_COLORSPACE_SRGB : STBIR_COLORSPACE_LINEAR, nullptr);
    if (!ok)
        throw RuntimeError("downscaling a " + std::to_string(rgba.width) + "x" + std::to_string(rgba.height) +
                           " texture failed");
    return out;
}

GlTexture uploadMaterialTexture(const Image8& image, bool srgb, int maxSize)
{
    const auto [width, height] = cappedTextureSize(image.width, image.height, maxSize);
    Image8 scaled;
    if (width != image.width || height != image.height)
        scaled = downscaleTexture(image, width, height, srgb);
    const Image8& rgba = scaled.data.empty() ? image : scaled;
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

GlTexture makeRenderTexture(GLenum format, int width, int height, GLenum filter, GLenum wrapS)
{
    GlTexture texture = GlTexture::create();
    glBindTexture(GL_TEXTURE_2D, texture.name());
    glTexStorage2D(GL_TEXTURE_2D, 1, format, width, height);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GLint(filter));
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GLint(filter));
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GLint(wrapS));
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
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

GlTexture makeDepthCompareTexture(int width, int height, bool stencil)
{
    GlTexture texture = GlTexture::create();
    glBindTexture(GL_TEXTURE_2D, texture.name());
    glTexStorage2D(GL_TEXTURE_2D, 1, stencil ? GL_DEPTH24_STENCIL8 : GL_DEPTH_COMPONENT24, width, height);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_COMPARE_MODE, GL_COMPARE_REF_TO_TEXTURE);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_COMPARE_FUNC, GL_LEQUAL);
    return texture;
}

} // namespace lumar
