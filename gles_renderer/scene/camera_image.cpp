#include "gles_renderer/scene/camera_image.h"

#include <algorithm>
#include <bit>

#include "core/error.h"
#include "gles_renderer/gl/gl_check.h"

namespace lumar {

CameraImage::CameraImage(int frameWidth, int frameHeight, int reduction)
    : width_(std::max(1, frameWidth / std::max(1, reduction))),
      height_(std::max(1, frameHeight / std::max(1, reduction))), texture_(GlTexture::create()),
      framebuffer_(GlFramebuffer::create())
{
    const int levels = int(std::bit_width(unsigned(std::max(width_, height_))));
    glBindTexture(GL_TEXTURE_2D, texture_.name());
    glTexStorage2D(GL_TEXTURE_2D, levels, GL_RGBA8, width_, height_);
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

} // namespace lumar
