#include "gles_renderer/background_pass.h"

#include <string>

#include "core/error.h"
#include "gles_renderer/gl_check.h"
#include "gles_renderer/shader_program.h"

namespace lumar {

BackgroundPass::BackgroundPass(const RenderTarget& target)
    : width_(target.width()), height_(target.height()), targetTexture_(target.colourTexture())
{
    if (targetTexture_ != 0)
        return;
    program_ = linkProgram(kBackgroundProgram);
    texture_ = GlTexture::create();
    emptyVertexArray_ = GlVertexArray::create();
    glUseProgram(program_.name());
    glUniform1i(uniformLocation(program_, "uCamera"), GLint(kTextureUnit));

    glActiveTexture(GL_TEXTURE0 + kTextureUnit);
    glBindTexture(GL_TEXTURE_2D, texture_.name());
    glTexStorage2D(GL_TEXTURE_2D, 1, GL_RGB8, width_, height_);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    checkGlError("creating the background pass");
}

void BackgroundPass::upload(GLuint texture, const Image8& rgb) const
{
    glActiveTexture(GL_TEXTURE0 + kTextureUnit);
    glBindTexture(GL_TEXTURE_2D, texture);
    // Rows of 3-byte pixels are tightly packed, not 4-byte aligned. Image row y goes to
    // texture row y, which the target keeps as image row y (see clipFromCamera).
    glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
    glTexSubImage2D(GL_TEXTURE_2D, 0, 0, 0, width_, height_, GL_RGB, GL_UNSIGNED_BYTE, rgb.data.data());
}

void BackgroundPass::draw(const Image8& rgb) const
{
    if (rgb.width != width_ || rgb.height != height_ || rgb.channels != 3 ||
        rgb.data.size() != size_t(width_) * size_t(height_) * 3) {
        throw InputError("background image is " + std::to_string(rgb.width) + "x" + std::to_string(rgb.height) + "x" +
                         std::to_string(rgb.channels) + ", the renderer needs " + std::to_string(width_) + "x" +
                         std::to_string(height_) + "x3");
    }
    if (targetTexture_ != 0) {
        // Straight into the framebuffer's own texture: the copy is exact by construction and
        // costs no fragment work.
        upload(targetTexture_, rgb);
        glBindTexture(GL_TEXTURE_2D, 0); // never leave the render target bound for sampling
        return;
    }
    upload(texture_.name(), rgb);
    glDisable(GL_DEPTH_TEST);
    glDisable(GL_CULL_FACE);
    glUseProgram(program_.name());
    glBindVertexArray(emptyVertexArray_.name());
    glDrawArrays(GL_TRIANGLES, 0, 3);
}

} // namespace lumar
