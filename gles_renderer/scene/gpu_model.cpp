#include "gles_renderer/scene/gpu_model.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstring>
#include <limits>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "core/error.h"
#include "gles_renderer/assets/convex_surface.h"
#include "gles_renderer/assets/gltf_rig.h"
#include "gles_renderer/assets/lafortune_material.h"
#include "gles_renderer/assets/mesh_simplify.h"
#include "gles_renderer/gl/gl_check.h"
#include "gles_renderer/gl/gpu_texture.h"
#include "gles_renderer/scene/mesh_features.h"
#include "gles_renderer/scene/uniform_blocks.h"

namespace lumar {
namespace {

// The stand-ins' levels (cells along the longest side), finest first; each two thirds to
// three quarters of the one before, so the chosen level's cells rarely span much less than kProxyMaxCellPixels.
constexpr int kProxyLevelCells[] = {kProxyMaxCells, 32, 24, 16, 12, 8};
// A coarser level is kept only where it removes at least this share of the triangles of the
// last level kept: a cube stays one level, a sphere seen small still gets coarser ones.
constexpr double kProxyMinTriangleSaving = 0.2;

size_t triangleCount(const std::vector<GltfPrimitive>& primitives)
{
    size_t count = 0;
    for (const GltfPrimitive& p : primitives)
        count += p.indices.size() / 3;
    return count;
}

struct Vertex {
    glm::vec3 position;
    glm::vec3 normal;
    glm::vec2 uv;
    glm::vec4 tangent;
};
static_assert(sizeof(Vertex) == 48, "Vertex must be tightly packed for the attribute offsets");

struct ExtraVertex {
    glm::vec4 color;
    glm::vec2 uv1;
};
static_assert(sizeof(ExtraVertex) == 24, "ExtraVertex must be tightly packed for the attribute offsets");

// glTF sampler state on an uploaded texture (0: lumar's default, trilinear and linear).
void applySampler(const GlTexture& texture, const GltfSampler& sampler)
{
    glBindTexture(GL_TEXTURE_2D, texture.name());
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, sampler.wrapS);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, sampler.wrapT);
    if (sampler.minFilter != 0)
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, sampler.minFilter);
    if (sampler.magFilter != 0)
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, sampler.magFilter);
    glBindTexture(GL_TEXTURE_2D, 0);
}

std::string describe(const GltfModel& model)
{
    return model.file.empty() ? std::string("(in-memory model)") : model.file.string();
}

void checkTextureIndex(const GltfModel& model, size_t materialIndex, const char* slot, int texture)
{
    if (texture < -1 || texture >= int(model.textures.size()))
        throw InputError(describe(model) + ": material " + std::to_string(materialIndex) + " " + slot +
                         " refers to texture " + std::to_string(texture) + " of " +
                         std::to_string(model.textures.size()));
}

void checkPrimitive(const GltfModel& model, size_t index)
{
    const GltfPrimitive& p = model.primitives[index];
    const std::string where = describe(model) + ": primitive " + std::to_string(index);
    const size_t n = p.positions.size();
    if (!(p.uvs1.empty() || p.uvs1.size() == n) || !(p.colors.empty() || p.colors.size() == n))
        throw InputError(where + ": " + std::to_string(n) + " positions but " + std::to_string(p.uvs1.size()) +
                         " second uvs, " + std::to_string(p.colors.size()) + " colours");
    if (p.normals.size() != n || p.uvs.size() != n || p.tangents.size() != n)
        throw InputError(where + ": " + std::to_string(n) + " positions but " + std::to_string(p.normals.size()) +
                         " normals, " + std::to_string(p.uvs.size()) + " uvs, " + std::to_string(p.tangents.size()) +
                         " tangents");
    if (n > size_t(std::numeric_limits<uint32_t>::max()))
        throw InputError(where + ": too many vertices");
    if (p.indices.size() % 3 != 0)
        throw InputError(where + ": " + std::to_string(p.indices.size()) +
                         " indices is not a whole number of triangles");
    if (p.indices.size() > size_t(std::numeric_limits<GLsizei>::max()))
        throw InputError(where + ": too many indices");
    for (const uint32_t i : p.indices)
        if (i >= n)
            throw InputError(where + ": index " + std::to_string(i) + " beyond " + std::to_string(n) + " vertices");
    if (p.material < -1 || p.material >= int(model.materials.size()))
        throw InputError(where + ": material " + std::to_string(p.material) + " of " +
                         std::to_string(model.materials.size()));
}

void checkTexture(const GltfModel& model, size_t index, GLint maxSize)
{
    const Image8& image = model.textures[index].image;
    if (image.channels != 4 || image.width < 1 || image.height < 1 || image.width > maxSize || image.height > maxSize ||
        image.data.size() != size_t(image.width) * size_t(image.height) * 4)
        throw InputError(describe(model) + ": texture " + std::to_string(index) + " is " + std::to_string(image.width) +
                         "x" + std::to_string(image.height) + "x" + std::to_string(image.channels) +
                         "; the renderer needs RGBA of at most " + std::to_string(maxSize) + " pixels a side");
}

// `images`: the model's textures as loaded (the thickness texture is read here, not uploaded).
GpuMaterial uploadMaterial(const GltfMaterial& m, const std::vector<GlTexture>& textures,
                           const std::vector<GltfTexture>& images, const DefaultTextures& defaults)
{
    const auto textureOr = [&](int index, const GlTexture& fallback) {
        return index >= 0 ? textures[size_t(index)].name() : fallback.name();
    };
    MaterialUniforms block;
    block.baseColorFactor = m.baseColorFactor;
    block.emissiveNormalScale = glm::vec4(m.emissiveFactor, m.normalTexture >= 0 ? m.normalScale : 0.0f);
    const auto has = [](int texture) { return texture >= 0 ? 1.0f : 0.0f; };
    block.textureFlags =
        glm::vec4(has(m.baseColorTexture), has(m.hasLafortune ? m.specularTexture : m.metallicRoughnessTexture),
                  has(m.lobeTexture), has(m.tangentRotationTexture));
    block.alphaUnlitOcclusion = glm::vec4(float(int(m.alphaMode)), m.alphaCutoff, m.unlit ? 1.0f : 0.0f,
                                          m.occlusionTexture >= 0 ? m.occlusionStrength : 0.0f);
    for (size_t slot = 0; slot < kGltfTextureSlots; ++slot) {
        const std::array<glm::vec3, 2> rows = m.uvTransforms[slot].rows();
        block.uvTransforms[2 * slot] = glm::vec4(rows[0], m.uvTransforms[slot].texCoord == 1 ? 1.0f : 0.0f);
        block.uvTransforms[2 * slot + 1] = glm::vec4(rows[1], 0.0f);
    }
    const GltfTransmission& t = m.transmission;
    const bool transmissive = t.factor > 0.0f;
    if (transmissive) {
        // F0 = ((ior - 1) / (ior + 1))^2 (KHR_materials_ior; 1 for its special value 0).
        const float f0 = t.ior == 0.0f ? 1.0f : std::pow((t.ior - 1.0f) / (t.ior + 1.0f), 2.0f);
        const float thickness = volumeThickness(t, images);
        block.transmission =
            glm::vec4(t.factor, thickness > 0.0f && t.ior >= 1.0f ? 1.0f / t.ior : 1.0f, f0, has(t.texture));
        // Beer-Lambert over the thickness (KHR_materials_volume): colour^(thickness/distance).
        glm::vec3 attenuation(1.0f);
        if (thickness > 0.0f && std::isfinite(t.attenuationDistance))
            attenuation = glm::pow(t.attenuationColor, glm::vec3(thickness / t.attenuationDistance));
        block.transmissionTint = glm::vec4(t.tint * attenuation, 1.0f);
        const std::array<glm::vec3, 2> rows = t.uvTransform.rows();
        block.transmissionUv[0] = glm::vec4(rows[0], t.uvTransform.texCoord == 1 ? 1.0f : 0.0f);
        block.transmissionUv[1] = glm::vec4(rows[1], 0.0f);
    }
    if (m.hasLafortune) {
        const LafortuneParams& l = m.lafortune;
        block.baseColorFactor = glm::vec4(l.diffuse, m.baseColorFactor.a);
        block.metallicRoughness = glm::vec4(m.metallicFactor, m.roughnessFactor, 1.0f, l.fresnelPhi);
        block.specularFactor = glm::vec4(l.specular, l.tangentRotation);
        block.lobeFactor = glm::vec4(l.lobe, l.exponent);
    } else {
        block.metallicRoughness = glm::vec4(m.metallicFactor, m.roughnessFactor, 0.0f, kMetallicRoughnessFresnelPhi);
    }

    GpuMaterial material;
    material.uniforms = GlBuffer::create();
    glBindBuffer(GL_UNIFORM_BUFFER, material.uniforms.name());
    glBufferData(GL_UNIFORM_BUFFER, sizeof(block), &block, GL_STATIC_DRAW);
    material.baseColor = textureOr(m.baseColorTexture, defaults.white);
    material.metallicRoughness = textureOr(m.metallicRoughnessTexture, defaults.white);
    material.normal = textureOr(m.normalTexture, defaults.flatNormal);
    material.emissive = textureOr(m.emissiveTexture, defaults.white);
    material.specular = textureOr(m.specularTexture, defaults.white);
    material.lobe = textureOr(m.lobeTexture, defaults.white);
    material.tangentRotation = textureOr(m.tangentRotationTexture, defaults.white);
    material.occlusion = textureOr(m.occlusionTexture, defaults.white);
    material.transmission = textureOr(transmissive ? t.texture : -1, defaults.white);
    material.transmissive = transmissive;
    if (transmissive) {
        float through = block.transmission.x * (1.0f - block.transmission.z) *
                        (block.transmissionTint.r + block.transmissionTint.g + block.transmissionTint.b) / 3.0f;
        if (!m.hasLafortune)
            through *= 1.0f - block.metallicRoughness.x;
        material.shadowOpacity = 1.0f - std::clamp(through, 0.0f, 1.0f);
    }
    material.doubleSided = m.doubleSided;
    material.alphaMode = m.alphaMode;
    const auto bit = [](bool on, uint32_t feature) { return on ? feature : 0U; };
    material.features =
        bit(m.baseColorTexture >= 0, mesh_feature::kBaseColorTexture) |
        bit((m.hasLafortune ? m.specularTexture : m.metallicRoughnessTexture) >= 0, mesh_feature::kSecondTexture) |
        bit(m.lobeTexture >= 0, mesh_feature::kLobeTexture) |
        bit(m.tangentRotationTexture >= 0, mesh_feature::kRotationTexture) |
        bit(m.hasLafortune, mesh_feature::kLafortune) |
        bit(block.emissiveNormalScale.w != 0.0f, mesh_feature::kNormalMap) |
        bit(glm::any(glm::greaterThan(m.emissiveFactor, glm::vec3(0.0f))), mesh_feature::kEmission) |
        bit(block.alphaUnlitOcclusion.w > 0.0f, mesh_feature::kOcclusionTexture) | bit(m.unlit, mesh_feature::kUnlit) |
        bit(m.alphaMode == GltfAlphaMode::Mask, mesh_feature::kAlphaMask) |
        bit(m.alphaMode == GltfAlphaMode::Blend, mesh_feature::kAlphaBlend) |
        bit(transmissive, mesh_feature::kTransmission) | glossFeatures(block) | reflectanceFeatures(block);
    return material;
}

std::vector<Vertex> interleave(const GltfPrimitive& p)
{
    std::vector<Vertex> vertices(p.positions.size());
    for (size_t i = 0; i < vertices.size(); ++i)
        vertices[i] = {p.positions[i], p.normals[i], p.uvs[i], p.tangents[i]};
    return vertices;
}

GpuPrimitive uploadPrimitive(const GltfPrimitive& p, size_t defaultMaterial, size_t source, GLenum usage)
{
    const std::vector<Vertex> vertices = interleave(p);

    GpuPrimitive primitive;
    primitive.source = source;
    primitive.modelFromMesh = glm::dmat4(p.modelFromMesh);
    primitive.material = p.material >= 0 ? size_t(p.material) : defaultMaterial;
    primitive.indexCount = GLsizei(p.indices.size());
    primitive.vertexArray = GlVertexArray::create();
    primitive.vertices = GlBuffer::create();
    primitive.indices = GlBuffer::create();

    glBindVertexArray(primitive.vertexArray.name());
    glBindBuffer(GL_ARRAY_BUFFER, primitive.vertices.name());
    glBufferData(GL_ARRAY_BUFFER, GLsizeiptr(vertices.size() * sizeof(Vertex)), vertices.data(), usage);
    const auto attribute = [](GLuint location, GLint components, size_t offset) {
        glEnableVertexAttribArray(location);
        glVertexAttribPointer(location, components, GL_FLOAT, GL_FALSE, sizeof(Vertex),
                              reinterpret_cast<const void*>(offset));
    };
    attribute(0, 3, offsetof(Vertex, position));
    attribute(1, 3, offsetof(Vertex, normal));
    attribute(2, 2, offsetof(Vertex, uv));
    attribute(3, 4, offsetof(Vertex, tangent));
    // Vertex colours and the second uv set only where the primitive has them: elsewhere the
    // attributes stay disabled and read MeshPass's constant white and (0, 0).
    if (!p.colors.empty() || !p.uvs1.empty()) {
        std::vector<ExtraVertex> extras(p.positions.size(), ExtraVertex{glm::vec4(1.0f), glm::vec2(0.0f)});
        for (size_t i = 0; i < extras.size(); ++i) {
            if (!p.colors.empty())
                extras[i].color = p.colors[i];
            if (!p.uvs1.empty())
                extras[i].uv1 = p.uvs1[i];
        }
        primitive.extras = GlBuffer::create();
        glBindBuffer(GL_ARRAY_BUFFER, primitive.extras.name());
        glBufferData(GL_ARRAY_BUFFER, GLsizeiptr(extras.size() * sizeof(ExtraVertex)), extras.data(), GL_STATIC_DRAW);
        glEnableVertexAttribArray(4);
        glVertexAttribPointer(4, 4, GL_FLOAT, GL_FALSE, sizeof(ExtraVertex),
                              reinterpret_cast<const void*>(offsetof(ExtraVertex, color)));
        glEnableVertexAttribArray(5);
        glVertexAttribPointer(5, 2, GL_FLOAT, GL_FALSE, sizeof(ExtraVertex),
                              reinterpret_cast<const void*>(offsetof(ExtraVertex, uv1)));
    }
    if (!p.positions.empty()) {
        glm::vec3 lo = p.positions[0], hi = p.positions[0];
        for (const glm::vec3& position : p.positions) {
            lo = glm::min(lo, position);
            hi = glm::max(hi, position);
        }
        primitive.boundsMin = lo;
        primitive.boundsMax = hi;
    }

    // 16-bit indices where they suffice: half the index traffic.
    glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, primitive.indices.name());
    if (vertices.size() <= 65536) {
        std::vector<uint16_t> shortIndices(p.indices.begin(), p.indices.end());
        glBufferData(GL_ELEMENT_ARRAY_BUFFER, GLsizeiptr(shortIndices.size() * sizeof(uint16_t)), shortIndices.data(),
                     GL_STATIC_DRAW);
        primitive.indexType = GL_UNSIGNED_SHORT;
    } else {
        glBufferData(GL_ELEMENT_ARRAY_BUFFER, GLsizeiptr(p.indices.size() * sizeof(uint32_t)), p.indices.data(),
                     GL_STATIC_DRAW);
        primitive.indexType = GL_UNSIGNED_INT;
    }
    glBindVertexArray(0);
    return primitive;
}

// Appends to `levels` the model simplified at each of `cellCounts` (finest first) that draws at
// least `minSaving` of the triangles fewer than the level kept before it, or than `triangles`
// before the first.
void appendLevels(const GltfModel& model, std::span<const int> cellCounts, double minSaving, size_t triangles,
                  size_t defaultMaterial, std::vector<GpuModel::ProxyLevel>& levels)
{
    for (const int cells : cellCounts) {
        const std::vector<GltfPrimitive> simplified = makeProxyPrimitives(model, cells);
        const size_t count = triangleCount(simplified);
        if (double(count) > (1.0 - minSaving) * double(triangles))
            continue;
        triangles = count;
        GpuModel::ProxyLevel& level = levels.emplace_back();
        level.cells = cells;
        // makeProxyPrimitives keeps the primitives' order: animation finds each one's source by it.
        for (size_t p = 0; p < simplified.size(); ++p)
            if (!simplified[p].indices.empty())
                level.primitives.push_back(uploadPrimitive(simplified[p], defaultMaterial, p, GL_STATIC_DRAW));
    }
}

} // namespace

DefaultTextures makeDefaultTextures()
{
    return {makeSolidTexture(255, 255, 255, 255), makeSolidTexture(128, 128, 255, 255)};
}

GpuModel uploadModel(const GltfModel& model, const DefaultTextures& defaults, int textureLimit)
{
    // Validate everything before the first upload, so bad input leaves no half-made model.
    GLint maxTextureSize = 0;
    glGetIntegerv(GL_MAX_TEXTURE_SIZE, &maxTextureSize);
    std::vector<bool> textureUsed(model.textures.size(), false);
    for (size_t m = 0; m < model.materials.size(); ++m) {
        const GltfMaterial& material = model.materials[m];
        const std::pair<const char*, int> slots[] = {{"base colour", material.baseColorTexture},
                                                     {"metallic-roughness", material.metallicRoughnessTexture},
                                                     {"normal", material.normalTexture},
                                                     {"emissive", material.emissiveTexture},
                                                     {"specular", material.specularTexture},
                                                     {"lobe", material.lobeTexture},
                                                     {"tangent rotation", material.tangentRotationTexture},
                                                     {"occlusion", material.occlusionTexture},
                                                     {"transmission", material.transmission.texture}};
        for (const auto& [slot, texture] : slots) {
            checkTextureIndex(model, m, slot, texture);
            if (texture >= 0)
                textureUsed[size_t(texture)] = true;
        }
    }
    for (size_t t = 0; t < model.textures.size(); ++t)
        if (textureUsed[t])
            checkTexture(model, t, maxTextureSize);
    for (size_t p = 0; p < model.primitives.size(); ++p)
        checkPrimitive(model, p);

    GpuModel gpu;
    gpu.boundsMin = model.boundsMin;
    gpu.boundsMax = model.boundsMax;
    gpu.convex = isConvexSurface(model);
    gpu.textures.resize(model.textures.size());
    for (size_t t = 0; t < model.textures.size(); ++t)
        if (textureUsed[t]) {
            gpu.textures[t] = uploadMaterialTexture(model.textures[t].image, model.textures[t].srgb, textureLimit);
            applySampler(gpu.textures[t], t < model.textureSamplers.size() ? model.textureSamplers[t] : GltfSampler{});
        }
    // A tangent-rotation map holds an angle that wraps (a / pi in [0, 1], and 1 turns T as 0
    // does): filtering across the wrap (bilinear, or the mipmaps' averages) gives a texel of
    // about 0.5, a 90 degree turn, and the brushed swirl of the paper's figure 1 showed the
    // wrap as a thin line through its centre. Sampled nearest, without mipmaps, each pixel
    // reads one texel's angle; the swirl's angle changes by under a degree from texel to
    // texel away from its centre, so the steps do not show.
    for (const GltfMaterial& material : model.materials)
        if (material.tangentRotationTexture >= 0) {
            glBindTexture(GL_TEXTURE_2D, gpu.textures[size_t(material.tangentRotationTexture)].name());
            glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
            glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
            glBindTexture(GL_TEXTURE_2D, 0);
        }
    for (const GltfMaterial& material : model.materials)
        gpu.materials.push_back(uploadMaterial(material, gpu.textures, model.textures, defaults));
    gpu.materials.push_back(uploadMaterial(GltfMaterial{}, gpu.textures, model.textures, defaults));
    const size_t defaultMaterial = gpu.materials.size() - 1;
    // Vertices a rig deforms are uploaded again with every pose.
    const bool deforms = model.rig && model.rig->deforms();
    const GLenum usage = deforms ? GL_DYNAMIC_DRAW : GL_STATIC_DRAW;
    for (size_t p = 0; p < model.primitives.size(); ++p)
        if (!model.primitives[p].indices.empty())
            gpu.primitives.push_back(uploadPrimitive(model.primitives[p], defaultMaterial, p, usage));
    if (deforms) {
        // Stand-ins simplified from the rest pose would show it in the maps and shadows while the
        // model moves: the model itself stands in, posed with it (model_pose_upload.h).
        GpuModel::ProxyLevel& level = gpu.proxyLevels.emplace_back();
        level.cells = kProxyMaxCells;
        for (size_t p = 0; p < model.primitives.size(); ++p)
            if (!model.primitives[p].indices.empty())
                level.primitives.push_back(uploadPrimitive(model.primitives[p], defaultMaterial, p, usage));
        checkGlError("uploading a model");
        return gpu;
    }
    // The frame's levels: kept where they save triangles against the model itself and the
    // level before (the shipped roadster: 9,616 -> 6,882 at 4096 cells and 6,281 at 1024; a
    // sphere or the milk truck save under 5 % and keep none).
    appendLevels(model, kFrameLevelCells, kFrameLevelMinTriangleSaving, triangleCount(model.primitives),
                 defaultMaterial, gpu.frameLevels);
    // The stand-ins: the finest always.
    appendLevels(model, kProxyLevelCells, kProxyMinTriangleSaving, std::numeric_limits<size_t>::max(), defaultMaterial,
                 gpu.proxyLevels);
    checkGlError("uploading a model");
    return gpu;
}

void interleaveVertices(const GltfPrimitive& posed, std::vector<std::byte>& bytes)
{
    const std::vector<Vertex> vertices = interleave(posed);
    bytes.resize(vertices.size() * sizeof(Vertex));
    std::memcpy(bytes.data(), vertices.data(), bytes.size());
}

void replaceVertices(const GpuPrimitive& primitive, std::span<const std::byte> interleaved)
{
    glBindBuffer(GL_ARRAY_BUFFER, primitive.vertices.name());
    glBufferData(GL_ARRAY_BUFFER, GLsizeiptr(interleaved.size()), interleaved.data(), GL_DYNAMIC_DRAW);
    glBindBuffer(GL_ARRAY_BUFFER, 0);
}

EnvironmentMapReads environmentMapReads(const GpuModel& model)
{
    EnvironmentMapReads reads;
    // The materials the primitives use (a model may carry others: a built-in shape's default
    // under its preset); the stand-ins use the same ones.
    for (const GpuPrimitive& primitive : model.primitives) {
        const GpuMaterial& material = model.materials[primitive.material];
        if ((material.features & mesh_feature::kUnlit) != 0)
            continue;
        const uint32_t floor =
            material.features & (mesh_feature::kGlossQuarter | mesh_feature::kGlossHalf | mesh_feature::kGlossMirror);
        reads.diffuse = reads.diffuse || (material.features & mesh_feature::kDiffuse) != 0 || floor == 0;
        reads.glossy1 = reads.glossy1 || floor == 0 || floor == mesh_feature::kGlossQuarter;
        reads.glossy2 = reads.glossy2 || floor != mesh_feature::kGlossMirror;
    }
    return reads;
}

std::array<glm::dvec3, 8> boxCorners(const glm::vec3& low, const glm::vec3& high, const glm::dmat4& transform)
{
    std::array<glm::dvec3, 8> corners;
    for (int i = 0; i < 8; ++i) {
        const glm::dvec3 local((i & 1) ? high.x : low.x, (i & 2) ? high.y : low.y, (i & 4) ? high.z : low.z);
        corners[size_t(i)] = glm::dvec3(transform * glm::dvec4(local, 1.0));
    }
    return corners;
}

std::array<glm::dvec3, 8> boundsCorners(const GpuModel& model, const glm::dmat4& transform)
{
    return boxCorners(model.boundsMin, model.boundsMax, transform);
}

const std::vector<GpuPrimitive>& framePrimitivesFor(const GpuModel& model, double modelPixels)
{
    if (std::isfinite(modelPixels) && modelPixels > 0.0)
        for (auto level = model.frameLevels.rbegin(); level != model.frameLevels.rend(); ++level)
            if (modelPixels / double(level->cells) <= kFrameMaxCellPixels)
                return level->primitives;
    return model.primitives;
}

const GpuModel::ProxyLevel& proxyLevelFor(const GpuModel& model, double modelPixels)
{
    // Coarsest first: the first level whose cells are small enough.
    if (std::isfinite(modelPixels) && modelPixels > 0.0)
        for (auto level = model.proxyLevels.rbegin(); level != model.proxyLevels.rend(); ++level)
            if (modelPixels / double(level->cells) <= kProxyMaxCellPixels)
                return *level;
    return model.proxyLevels.front();
}

} // namespace lumar
