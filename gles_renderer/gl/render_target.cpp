#include "gles_renderer/gl/render_target.h"

#include <string>

#include "core/error.h"
#include "core/log.h"
#include "gles_renderer/gl/gl_check.h"

namespace lumar {
namespace {

GlRenderbuffer makeRenderbuffer(GLenum format, int width, int height, int samples)
{
    GlRenderbuffer buffer = GlRenderbuffer::create();
    glBindRenderbuffer(GL_RENDERBUFFER, buffer.name());
    if (samples > 1)
        glRenderbufferStorageMultisample(GL_RENDERBUFFER, samples, format, width, height);
    else
        glRenderbufferStorage(GL_RENDERBUFFER, format, width, height);
    return buffer;
}

} // namespace

RenderTarget::RenderTarget(int width, int height, int samples) : width_(width), height_(height), samples_(samples)
{
    GLint maxSize = 0;
    glGetIntegerv(GL_MAX_RENDERBUFFER_SIZE, &maxSize);
    if (width < 1 || height < 1 || width > maxSize || height > maxSize)
        throw RuntimeError("cannot render at " + std::to_string(width) + "x" + std::to_string(height) +
                           ": GL renderbuffers are limited to " + std::to_string(maxSize));
    GLint maxSamples = 1;
    glGetIntegerv(GL_MAX_SAMPLES, &maxSamples);
    if (samples_ > maxSamples) {
        LUMAR_LOG(Render, Warn) << samples_ << "x multisampling requested, GL offers at most " << maxSamples;
        samples_ = maxSamples;
    }
    if (samples_ < 1)
        samples_ = 1;

    depth_ = makeRenderbuffer(GL_DEPTH_COMPONENT24, width, height, samples_);
    drawFramebuffer_ = GlFramebuffer::create();
    glBindFramebuffer(GL_FRAMEBUFFER, drawFramebuffer_.name());
    if (samples_ > 1) {
        colour_ = makeRenderbuffer(GL_RGBA8, width, height, samples_);
        glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, colour_.name());
    } else {
        colourTexture_ = GlTexture::create();
        glBindTexture(GL_TEXTURE_2D, colourTexture_.name());
        glTexStorage2D(GL_TEXTURE_2D, 1, GL_RGBA8, width, height);
        glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, colourTexture_.name(), 0);
    }
    glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, depth_.name());
    checkFramebufferComplete("render target");

    if (samples_ > 1) {
        resolvedColour_ = makeRenderbuffer(GL_RGBA8, width, height, 1);
        resolvedFramebuffer_ = GlFramebuffer::create();
        glBindFramebuffer(GL_FRAMEBUFFER, resolvedFramebuffer_.name());
        glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, resolvedColour_.name());
        checkFramebufferComplete("multisample resolve target");
    }
    checkGlError("creating the render target");
}

void RenderTarget::bindForDrawing() const
{
    glBindFramebuffer(GL_FRAMEBUFFER, drawFramebuffer_.name());
    glViewport(0, 0, width_, height_);
}

void RenderTarget::finishFrame() const
{
    glBindFramebuffer(GL_READ_FRAMEBUFFER, drawFramebuffer_.name());
    if (samples_ > 1) {
        glBindFramebuffer(GL_DRAW_FRAMEBUFFER, resolvedFramebuffer_.name());
        glBlitFramebuffer(0, 0, width_, height_, 0, 0, width_, height_, GL_COLOR_BUFFER_BIT, GL_NEAREST);
        const GLenum discarded[] = {GL_COLOR_ATTACHMENT0, GL_DEPTH_ATTACHMENT};
        glInvalidateFramebuffer(GL_READ_FRAMEBUFFER, 2, discarded);
    } else {
        const GLenum discarded[] = {GL_DEPTH_ATTACHMENT};
        glInvalidateFramebuffer(GL_READ_FRAMEBUFFER, 1, discarded);
    }
}

void RenderTarget::resolveColour() const
{
    if (samples_ <= 1)
        return;
    glBindFramebuffer(GL_READ_FRAMEBUFFER, drawFramebuffer_.name());
    glBindFramebuffer(GL_DRAW_FRAMEBUFFER, resolvedFramebuffer_.name());
    glBlitFramebuffer(0, 0, width_, height_, 0, 0, width_, height_, GL_COLOR_BUFFER_BIT, GL_NEAREST);
}

GLuint RenderTarget::readFramebuffer() const
{
    return samples_ > 1 ? resolvedFramebuffer_.name() : drawFramebuffer_.name();
}

} // namespace lumar
