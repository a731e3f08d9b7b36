// The phantoms' depth as the frame camera sees them, at the camera image's size: where a
// phantom drawn into an environment map takes its colour from the camera image
// (shaders_es/phantom.frag), this tells whether the camera saw that point or another phantom
// (or another part of the same one) stood in front of it.
#pragma once

#include <span>
#include <vector>

#include <glm/glm.hpp>

#include "gles_renderer/gl/gl_object.h"
#include "gles_renderer/scene/gpu_model.h"
#include "gles_renderer/scene/mesh_pass.h"
#include "gles_renderer/scene/scene_renderer.h"

namespace lumar {

class PhantomDepth {
public:
    // A width x height depth texture, compared on lookup (a sampler2DShadow, linear: the
    // fraction of the four nearest texels a point lies in front of).
    PhantomDepth(int width, int height);

    // Draws the phantoms among `items` (poses in the frame camera's frame) with the frame
    // camera's projection. Leaves the framebuffer binding, viewport and depth state changed.
    void render(const MeshPass& meshes, const std::vector<GpuModel>& models, std::span<const DrawItem> items,
                const glm::mat4& clipFromCamera);

    [[nodiscard]] GLuint texture() const { return texture_.name(); }

private:
    int width_;
    int height_;
    GlTexture texture_;
    GlFramebuffer framebuffer_;
    std::vector<DrawItem> phantoms_; // per-frame scratch
};

} // namespace lumar
