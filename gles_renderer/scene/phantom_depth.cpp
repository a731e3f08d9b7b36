#include "gles_renderer/scene/phantom_depth.h"

#include "core/error.h"
#include "gles_renderer/gl/gl_check.h"
#include "gles_renderer/gl/gpu_texture.h"

namespace lumar {
namespace {

// Slope-scaled depth offset of the drawn phantoms, so the surface the camera saw passes its
// own test: a lookup interpolates the four texels round the point, up to one texel away in x
// and in y, where the surface's depth differs by up to twice the steepest slope per texel;
// the constant term covers the rounding of the two paths that compute the same depth.
constexpr float kSlopeOffset = 2.5f;
constexpr float kConstantOffset = 8.0f;

} // namespace

PhantomDepth::PhantomDepth(int width, int height)
    : width_(width), height_(height), texture_(makeDepthCompareTexture(width, height)),
      framebuffer_(GlFramebuffer::create())
{
    glBindFramebuffer(GL_DRAW_FRAMEBUFFER, framebuffer_.name());
    glFramebufferTexture2D(GL_DRAW_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_TEXTURE_2D, texture_.name(), 0);
    const GLenum none = GL_NONE;
    glDrawBuffers(1, &none);
    if (glCheckFramebufferStatus(GL_DRAW_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE)
        throw RuntimeError("the phantoms' camera depth framebuffer is incomplete");
    checkGlError("creating the phantoms' camera depth texture");
}

void PhantomDepth::render(const MeshPass& meshes, const std::vector<GpuModel>& models, std::span<const DrawItem> items,
                          const glm::mat4& clipFromCamera)
{
    phantoms_.clear();
    for (const DrawItem& item : items)
        if (item.phantom)
            phantoms_.push_back(item);
    glBindFramebuffer(GL_DRAW_FRAMEBUFFER, framebuffer_.name());
    glViewport(0, 0, width_, height_);
    glDepthMask(GL_TRUE);
    glClearDepthf(1.0f);
    glClear(GL_DEPTH_BUFFER_BIT);
    FrameUniforms frame;
    frame.clipFromCamera = clipFromCamera;
    glEnable(GL_POLYGON_OFFSET_FILL);
    glPolygonOffset(kSlopeOffset, kConstantOffset);
    // Only phantoms are passed, so the pass draws depth alone and shades nothing.
    meshes.draw(frame, models, phantoms_, {}, -1, MeshPass::Phantoms::DepthOnly);
    glDisable(GL_POLYGON_OFFSET_FILL);
    checkGlError("drawing the phantoms' camera depth");
}

} // namespace lumar
