// A GltfModel uploaded to GL: one vertex array per primitive, one uniform buffer per
// material, its textures; everything the mesh pass binds to draw it.
#pragma once

#include <cstddef>
#include <vector>

#include <glm/glm.hpp>

#include "gles_renderer/gl_object.h"
#include "gles_renderer/gltf_model.h"

namespace lumar {

// Stand-ins for absent material textures, shared by every model.
struct DefaultTextures {
    GlTexture white;      // every colour and parameter map: the factor alone
    GlTexture flatNormal; // tangent-space +z
};

struct GpuMaterial {
    GlBuffer uniforms; // a MaterialUniforms block
    // Texture names, owned by the GpuModel or by DefaultTextures.
    GLuint baseColor = 0;
    GLuint metallicRoughness = 0;
    GLuint normal = 0;
    GLuint emissive = 0;
    GLuint specular = 0;
    GLuint lobe = 0;
    GLuint tangentRotation = 0;
    bool doubleSided = false;
};

struct GpuPrimitive {
    glm::dmat4 modelFromMesh{1.0};
    GlBuffer vertices; // interleaved position, normal, uv, tangent
    GlBuffer indices;
    GlVertexArray vertexArray;
    GLsizei indexCount = 0;
    GLenum indexType = GL_UNSIGNED_INT;
    size_t material = 0; // index into GpuModel::materials
};

struct GpuModel {
    glm::vec3 boundsMin{0.0f}, boundsMax{0.0f}; // model space: the environment map's centre
    std::vector<GlTexture> textures;            // parallel to GltfModel::textures; unused ones stay empty
    std::vector<GpuMaterial> materials;         // the model's materials, then glTF's default material
    std::vector<GpuPrimitive> primitives;
    // The same model simplified by vertex clustering (mesh_simplify.h), drawn into the
    // environment maps where it spans tens of pixels; same materials.
    std::vector<GpuPrimitive> proxyPrimitives;
};

// Checks every size and index of `model` (InputError "FILE: what is wrong") and uploads it.
GpuModel uploadModel(const GltfModel& model, const DefaultTextures& defaults);

} // namespace lumar
