#include "gles_renderer/gl/frame_readback.h"

#include <algorithm>

#include "core/log.h"
#include "core/pixel_pack.h"
#include "gles_renderer/gl/gl_check.h"

namespace lumar {

FrameReadback::FrameReadback(GLuint framebuffer, int width, int height)
    : framebuffer_(framebuffer), width_(width), height_(height)
{
    glBindFramebuffer(GL_READ_FRAMEBUFFER, framebuffer_);
    GLint format = 0, type = 0;
    glGetIntegerv(GL_IMPLEMENTATION_COLOR_READ_FORMAT, &format);
    glGetIntegerv(GL_IMPLEMENTATION_COLOR_READ_TYPE, &type);
    readsRgbDirectly_ = format == GL_RGB && type == GL_UNSIGNED_BYTE;
    if (!readsRgbDirectly_)
        rgba_.resize(size_t(width_) * size_t(std::min(height_, kReadbackRowsPerRead)) * 4);
    LUMAR_LOG(Render, Debug) << "readback as " << (readsRgbDirectly_ ? "RGB" : "RGBA, repacked to RGB");
    checkGlError("setting up frame readback");
}

void FrameReadback::read(Image8& rgb)
{
    rgb.reshape(width_, height_, 3);
    glBindFramebuffer(GL_READ_FRAMEBUFFER, framebuffer_);
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    if (readsRgbDirectly_) {
        glReadPixels(0, 0, width_, height_, GL_RGB, GL_UNSIGNED_BYTE, rgb.data.data());
    } else {
        // The first read waits for the frame; the later strips read the finished one.
        uint8_t* out = rgb.data.data();
        for (int y = 0; y < height_; y += kReadbackRowsPerRead) {
            const int rows = std::min(kReadbackRowsPerRead, height_ - y);
            glReadPixels(0, y, width_, rows, GL_RGBA, GL_UNSIGNED_BYTE, rgba_.data());
            const size_t pixels = size_t(width_) * size_t(rows);
            packRgbaToRgb(rgba_.data(), out, pixels);
            out += pixels * 3;
        }
    }
    checkGlError("reading the frame back");
}

} // namespace lumar
