// Pass 2 of a frame: the models, depth-tested and shaded by mesh.vert / mesh.frag.
#pragma once

#include <span>
#include <vector>

#include "gles_renderer/gl_object.h"
#include "gles_renderer/gpu_model.h"
#include "gles_renderer/scene_renderer.h"
#include "gles_renderer/uniform_blocks.h"

namespace lumar {

class MeshPass {
public:
    // Texture units of the material maps and the environment map.
    static constexpr GLuint kBaseColorUnit = 0;
    static constexpr GLuint kMetallicRoughnessUnit = 1;
    static constexpr GLuint kNormalUnit = 2;
    static constexpr GLuint kEmissiveUnit = 3;
    static constexpr GLuint kEnvironmentUnit = 4;

    MeshPass();

    // Draws `items` into the bound framebuffer (which must have been cleared of depth).
    // Every item's model id must index `models` (the caller checks).
    void draw(const FrameUniforms& frame, GLuint environmentMap, const std::vector<GpuModel>& models,
              std::span<const DrawItem> items) const;

private:
    GlProgram program_;
    GLint cameraFromMeshLocation_;
    GLint normalFromMeshLocation_;
    GlBuffer frameUniforms_;
};

} // namespace lumar
