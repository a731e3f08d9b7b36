#include "gles_renderer/scene/camera_image.h"

#include <algorithm>
#include <bit>
#include <cmath>

#include "core/error.h"
#include "gles_renderer/gl/gl_check.h"
#include "gles_renderer/scene/frame_shape.h"

namespace lumar {

namespace {

// Where a linear filter reads along one axis for each texel of a `to`-texel image stretched
// over a `from`-texel one: the texel centre (x + 0.5) scaled to the source, between the two
// source texels round it, clamped to the edge (GL's linear minification and a scaled blit).
struct Taps {
    std::vector<int> first;
    std::vector<int> second;
    std::vector<float> weight; // of `second`
};

Taps linearTaps(int from, int to)
{
    Taps taps;
    taps.first.resize(size_t(to));
    taps.second.resize(size_t(to));
    taps.weight.resize(size_t(to));
    const double scale = double(from) / double(to);
    for (int x = 0; x < to; ++x) {
        const double u = (x + 0.5) * scale - 0.5;
        const double below = std::floor(u);
        const int i = int(below);
        taps.first[size_t(x)] = std::clamp(i, 0, from - 1);
        taps.second[size_t(x)] = std::clamp(i + 1, 0, from - 1);
        taps.weight[size_t(x)] = float(u - below);
    }
    return taps;
}

// `to` (RGBA, its size set) from `from` (3 or 4 channels) by linear filtering; alpha is 1.
void resampleLinear(const Image8& from, Image8& to)
{
    const Taps columns = linearTaps(from.width, to.width);
    const Taps rows = linearTaps(from.height, to.height);
    const size_t channels = size_t(from.channels);
    for (int y = 0; y < to.height; ++y) {
        const uint8_t* top = from.row(rows.first[size_t(y)]);
        const uint8_t* bottom = from.row(rows.second[size_t(y)]);
        const float wy = rows.weight[size_t(y)];
        uint8_t* out = to.row(y);
        for (int x = 0; x < to.width; ++x, out += 4) {
            const size_t left = size_t(columns.first[size_t(x)]) * channels;
            const size_t right = size_t(columns.second[size_t(x)]) * channels;
            const float wx = columns.weight[size_t(x)];
            for (size_t c = 0; c < 3; ++c) {
                const float upper = float(top[left + c]) + wx * float(int(top[right + c]) - int(top[left + c]));
                const float lower =
                    float(bottom[left + c]) + wx * float(int(bottom[right + c]) - int(bottom[left + c]));
                out[c] = uint8_t(upper + wy * (lower - upper) + 0.5f);
            }
            out[3] = 255;
        }
    }
}

} // namespace

CameraImage::CameraImage(int frameWidth, int frameHeight, int reduction)
    : frameWidth_(frameWidth), frameHeight_(frameHeight), width_(std::max(1, frameWidth / std::max(1, reduction))),
      height_(std::max(1, frameHeight / std::max(1, reduction))),
      levelCount_(int(std::bit_width(unsigned(std::max(width_, height_))))), texture_(GlTexture::create()),
      framebuffer_(GlFramebuffer::create())
{
    glBindTexture(GL_TEXTURE_2D, texture_.name());
    glTexStorage2D(GL_TEXTURE_2D, levelCount_, GL_RGBA8, width_, height_);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR_MIPMAP_LINEAR);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    glBindFramebuffer(GL_DRAW_FRAMEBUFFER, framebuffer_.name());
    glFramebufferTexture2D(GL_DRAW_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, texture_.name(), 0);
    if (glCheckFramebufferStatus(GL_DRAW_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE)
        throw RuntimeError("the camera image's framebuffer is incomplete");
    checkGlError("creating the camera image texture");
}

void CameraImage::capture(const RenderTarget& target)
{
    target.resolveColour();
    glBindFramebuffer(GL_READ_FRAMEBUFFER, target.readFramebuffer());
    glBindFramebuffer(GL_DRAW_FRAMEBUFFER, framebuffer_.name());
    // Linear filtering averages 2 x 2 of the 4 x 4 pixels each texel covers; the mipmaps
    // below then filter what the blit skipped once the texture is seen from afar.
    glBlitFramebuffer(0, 0, target.width(), target.height(), 0, 0, width_, height_, GL_COLOR_BUFFER_BIT, GL_LINEAR);
    glBindTexture(GL_TEXTURE_2D, texture_.name());
    glGenerateMipmap(GL_TEXTURE_2D);
    checkGlError("capturing the camera image");
}

void CameraImage::reduce(const Image8& rgb)
{
    checkRgbFrame(rgb, frameWidth_, frameHeight_, "camera image");
    levels_.resize(size_t(levelCount_));
    for (int level = 0; level < levelCount_; ++level) {
        Image8& image = levels_[size_t(level)];
        image.reshape(std::max(1, width_ >> level), std::max(1, height_ >> level), 4);
        resampleLinear(level == 0 ? rgb : levels_[size_t(level - 1)], image);
    }
}

void CameraImage::uploadReduced()
{
    if (levels_.empty())
        throw RuntimeError("CameraImage::uploadReduced() without a reduce()");
    glBindTexture(GL_TEXTURE_2D, texture_.name());
    glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
    for (size_t level = 0; level < levels_.size(); ++level) {
        const Image8& image = levels_[level];
        glTexSubImage2D(GL_TEXTURE_2D, GLint(level), 0, 0, image.width, image.height, GL_RGBA, GL_UNSIGNED_BYTE,
                        image.data.data());
    }
    checkGlError("uploading the camera image");
}

} // namespace lumar
