#include "gles_renderer/ibl_gpu/environment_lighting.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <utility>
#include <vector>

#include "core/error.h"
#include "gles_renderer/assets/environment_map.h"
#include "gles_renderer/gl/gl_check.h"

namespace lumar {
namespace {

// The largest finite half float: brighter texels (the sun) would become infinity.
constexpr float kHalfFloatMax = 65504.0f;

ImageF scaledForHalfFloat(const ImageF& equirect, float intensity)
{
    ImageF out(equirect.width, equirect.height, 3);
    for (size_t i = 0; i < out.data.size(); ++i) {
        const float v = equirect.data[i] * intensity;
        out.data[i] = std::isfinite(v) ? std::clamp(v, 0.0f, kHalfFloatMax) : 0.0f;
    }
    return out;
}

// One level down the mip chain: each texel the mean of a 2x2 block (the last row/column is
// repeated for odd sizes).
ImageF halved(const ImageF& src)
{
    ImageF dst(std::max(1, src.width / 2), std::max(1, src.height / 2), 3);
    for (int y = 0; y < dst.height; ++y) {
        const int y0 = std::min(2 * y, src.height - 1);
        const int y1 = std::min(2 * y + 1, src.height - 1);
        for (int x = 0; x < dst.width; ++x) {
            const int x0 = std::min(2 * x, src.width - 1);
            const int x1 = std::min(2 * x + 1, src.width - 1);
            float* out = dst.at(x, y);
            for (int c = 0; c < 3; ++c)
                out[c] = 0.25f * (src.at(x0, y0)[c] + src.at(x1, y0)[c] + src.at(x0, y1)[c] + src.at(x1, y1)[c]);
        }
    }
    return dst;
}

ImageF uniformEnvironment(float radiance)
{
    ImageF image(8, 4, 3);
    std::fill(image.data.begin(), image.data.end(), radiance);
    return image;
}

} // namespace

EnvironmentLighting::EnvironmentLighting(int faceSize) : faceSize_(faceSize)
{
    set(uniformEnvironment(1.0f), 1.0f);
}

void EnvironmentLighting::set(const ImageF& equirect, float intensity)
{
    if (!std::isfinite(intensity) || intensity < 0.0f)
        throw InputError("environment intensity must be a finite number >= 0, got " + std::to_string(intensity));
    if (equirect.channels != 3 || equirect.width < 2 || equirect.height < 1 ||
        equirect.data.size() != size_t(equirect.width) * size_t(equirect.height) * 3)
        throw InputError("the environment map must be a non-empty 3-channel image");

    // The mip chain is built on the CPU: glGenerateMipmap needs a colour-renderable format,
    // which half floats are not in core GLES 3.0.
    std::vector<ImageF> levels;
    levels.push_back(scaledForHalfFloat(equirect, intensity));
    while (levels.back().width > 1 || levels.back().height > 1)
        levels.push_back(halved(levels.back()));
    GLint maxTextureSize = 0;
    glGetIntegerv(GL_MAX_TEXTURE_SIZE, &maxTextureSize);
    size_t first = 0;
    while (levels[first].width > maxTextureSize || levels[first].height > maxTextureSize)
        ++first;
    // Faces read at lod log2(width / (4 faceSize)) and finer levels are never read: from 1k
    // with 64-texel faces, levels 0 and 1 are 15/16 of the texture (5.3 MB of 5.6 resident
    // on llvmpipe). Skipping whole levels keeps every lookup where it was, the lod falling
    // by as many as the width halves.
    while (faceSize_ > 0 && first + 1 < levels.size() && levels[first + 1].width >= 4 * faceSize_)
        ++first;

    GlTexture texture = GlTexture::create();
    glBindTexture(GL_TEXTURE_2D, texture.name());
    glTexStorage2D(GL_TEXTURE_2D, GLsizei(levels.size() - first), GL_RGB16F, levels[first].width, levels[first].height);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
    for (size_t i = first; i < levels.size(); ++i)
        glTexSubImage2D(GL_TEXTURE_2D, GLint(i - first), 0, 0, levels[i].width, levels[i].height, GL_RGB, GL_FLOAT,
                        levels[i].data.data());
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR_MIPMAP_LINEAR);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_REPEAT); // longitude wraps around
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    checkGlError("uploading the environment map");

    equirect_ = std::move(texture);
    equirectWidth_ = levels[first].width;
    ++generation_;
}

void EnvironmentLighting::setRotation(const glm::dmat3& environmentFromCamera)
{
    environmentFromCamera_ = environmentFromCamera;
}

} // namespace lumar
