// A GltfModel uploaded to GL: one vertex array per primitive, one uniform buffer per
// material, its textures; everything the mesh pass binds to draw it.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include <glm/glm.hpp>

#include "gles_renderer/assets/gltf_model.h"
#include "gles_renderer/gl/gl_object.h"

namespace lumar {

// Stand-ins for absent material textures, shared by every model.
struct DefaultTextures {
    GlTexture white;      // every colour and parameter map: the factor alone
    GlTexture flatNormal; // tangent-space +z
};

// The two 1 x 1 textures DefaultTextures holds. Needs a current context.
[[nodiscard]] DefaultTextures makeDefaultTextures();

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
    GLuint occlusion = 0;
    GLuint transmission = 0;
    bool doubleSided = false;
    uint32_t features = 0; // mesh_feature bits of the material (mesh_features.h)
    // Mask and Blend primitives are drawn in the shaded pass alone (a depth-only prepass
    // must skip them); Blend ones after the opaque ones, back to front, without depth writes.
    GltfAlphaMode alphaMode = GltfAlphaMode::Opaque;
    // Light passes through (GltfTransmission): drawn with the Blend ones, after the opaque.
    bool transmissive = false;
    // The share of the light a transmissive surface stops in the shadow map (depth_only.frag's
    // opacity without the BLEND coverage): what it reflects (F0), what its tint absorbs, the
    // metal share of a metallic-roughness material.
    float shadowOpacity = 1.0f;
};

// Whether what lies behind the material shows through it (alphaMode BLEND, or transmission:
// glass): the mesh pass draws it after the opaque primitives, back to front, and the shadow
// map lets part of the light through it.
[[nodiscard]] inline bool isTransparent(const GpuMaterial& material)
{
    return material.alphaMode == GltfAlphaMode::Blend || material.transmissive;
}

struct GpuPrimitive {
    glm::dmat4 modelFromMesh{1.0};
    GlBuffer vertices;                          // interleaved position, normal, uv, tangent
    GlBuffer extras;                            // interleaved colour, uv1 where the primitive has either (else empty)
    glm::vec3 boundsMin{0.0f}, boundsMax{0.0f}; // its bounding box, mesh space (rest pose)
    GlBuffer indices;
    GlVertexArray vertexArray;
    GLsizei indexCount = 0;
    GLenum indexType = GL_UNSIGNED_INT;
    size_t material = 0; // index into GpuModel::materials
    size_t source = 0;   // index into GltfModel::primitives of what it was made from (animation poses it)
};

struct GpuModelPose; // model_pose_upload.h

struct GpuModel {
    glm::vec3 boundsMin{0.0f}, boundsMax{0.0f}; // model space: the environment map's centre
    std::vector<GlTexture> textures;            // parallel to GltfModel::textures; unused ones stay empty
    std::vector<GpuMaterial> materials;         // the model's materials, then glTF's default material
    std::vector<GpuPrimitive> primitives;
    // The same model simplified (mesh_simplify.h) to several error bounds, drawn into the
    // environment maps where it spans tens of pixels; same materials.
    struct ProxyLevel {
        int cells = 0; // its surface within a "cell", the model's longest side / cells
        std::vector<GpuPrimitive> primitives;
    };
    std::vector<ProxyLevel> proxyLevels; // finest first; never empty after uploadModel
    // The model simplified far below a pixel of the frame (framePrimitivesFor): flat stretches
    // a modeller subdivided drawn as fewer, larger triangles. Finest first; empty where no
    // level saves enough triangles (kFrameLevelMinTriangleSaving), and for deforming models.
    std::vector<ProxyLevel> frameLevels;
    // An animated model's posing state (model_pose_upload.h); null for a still one. Its
    // bounds, transforms and (deforming models) vertices change with every pose, and
    // poseGeneration counts the poses.
    std::shared_ptr<GpuModelPose> pose;
    uint64_t poseGeneration = 0;
    // Its surface bounds a convex body (assets/convex_surface.h), as uploaded: ShadowPass lets
    // a single convex phantom write its depth in the apply pass.
    bool convex = false;
};

// Cells along a model's longest side for its finest environment-map stand-in: a
// neighbour in a 64-pixel face rarely spans more pixels than that.
inline constexpr int kProxyMaxCells = 48;
// The widest a stand-in's cell may appear, in pixels, when its level is chosen: its surface
// strays less than a cell from the model's, and llvmpipe shades every triangle in whole 4x4
// blocks, so sub-pixel triangles (the finest level seen from afar) cost up to 16
// fragment-shader runs per pixel they cover.
inline constexpr double kProxyMaxCellPixels = 1.0;

// The stand-in to draw for `model` when its longest side spans `modelPixels` pixels of the
// view (<= 0 or not finite: unknown, the finest): the coarsest level whose cell spans at
// most kProxyMaxCellPixels, else the finest.
const GpuModel::ProxyLevel& proxyLevelFor(const GpuModel& model, double modelPixels);

// The frame's levels (GpuModel::frameLevels), cells along the longest side, finest first.
inline constexpr int kFrameLevelCells[] = {4096, 1024};
// The widest a frame level's cell may appear, in pixels. A level strays from the model by its
// simplification bound, a fifth of a cell (mesh_simplify.cpp), and no sampled vertex by more
// than 0.6 of one: at half a pixel a cell, silhouettes move by a tenth of a pixel (at most
// 0.3), which the frame's single sample per pixel shows as a handful of edge pixels.
inline constexpr double kFrameMaxCellPixels = 0.5;
// A frame level is kept only where it draws at least this share fewer triangles than the
// level (or the model) before it: on llvmpipe a triangle's edges are most of its shading
// (mesh_pass.h), so fewer triangles is what a level is for.
inline constexpr double kFrameLevelMinTriangleSaving = 0.05;

// What to draw for `model` in the frame when its longest side spans `modelPixels` pixels
// (<= 0 or not finite: unknown): the coarsest frame level whose cell spans at most
// kFrameMaxCellPixels, else the model itself.
const std::vector<GpuPrimitive>& framePrimitivesFor(const GpuModel& model, double modelPixels);

// Which of an object's own environment maps its shading can read (mesh.frag, in the frame and
// in other objects' cube faces alike): the mirror map always; the diffuse map where a
// material has a diffuse term (HAS_DIFFUSE) or a glossiness floor below 1/4; glossy-1 below
// 1/2; glossy-2 below 1 (GLOSS_FLOOR, glossFeatures: the Fresnel factor only raises the
// glossiness, so the maps below a material's floor weigh 0 and its variant leaves them out).
// Unlit materials read none. A chrome object reads its mirror map alone: the SH projection,
// the diffuse map and both glossy prefilters of its set are work nothing looks at.
struct EnvironmentMapReads {
    bool diffuse = false; // and the SH projection it is made from
    bool glossy1 = false; // cascaded from glossy-2: needs it too
    bool glossy2 = false;

    [[nodiscard]] bool covers(const EnvironmentMapReads& other) const
    {
        return (diffuse || !other.diffuse) && (glossy1 || !other.glossy1) && (glossy2 || !other.glossy2);
    }
};
[[nodiscard]] EnvironmentMapReads environmentMapReads(const GpuModel& model);

// The eight corners of the box [low, high], each mapped by the affine `transform`: corner i
// takes high's x, y, z where bits 0, 1, 2 of i are set.
std::array<glm::dvec3, 8> boxCorners(const glm::vec3& low, const glm::vec3& high, const glm::dmat4& transform);
// boxCorners of `model`'s bounding box (boundsMin, boundsMax), e.g. by cameraFromModel.
std::array<glm::dvec3, 8> boundsCorners(const GpuModel& model, const glm::dmat4& transform);

// Checks every size and index of `model` (InputError "FILE: what is wrong") and uploads it.
// Textures larger than `textureLimit` (0: no limit) are scaled down to fit on upload.
// A model whose rig deforms it (skins, morph targets) gets one stand-in level, the model itself,
// posed with it.
GpuModel uploadModel(const GltfModel& model, const DefaultTextures& defaults, int textureLimit = 0);

// `posed`'s vertices interleaved as uploadPrimitive lays them out, into `bytes`.
void interleaveVertices(const GltfPrimitive& posed, std::vector<std::byte>& bytes);
// Replaces all of `primitive`'s vertices (the same count) with `interleaved` (orphaning the
// buffer, so a draw still reading the old ones does not stall the upload).
void replaceVertices(const GpuPrimitive& primitive, std::span<const std::byte> interleaved);

} // namespace lumar
