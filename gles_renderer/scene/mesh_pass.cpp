#include "gles_renderer/scene/mesh_pass.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <utility>

#include <glm/gtc/type_ptr.hpp>

#include "gles_renderer/gl/gl_check.h"
#include "gles_renderer/gl/shader_program.h"
#include "gles_renderer/scene/mesh_features.h"

namespace lumar {

// Skips GL calls that would not change state: llvmpipe validates state on every change.
class StateCache {
public:
    void setCulling(bool enabled)
    {
        if (culling_ == int(enabled))
            return;
        culling_ = int(enabled);
        if (enabled)
            glEnable(GL_CULL_FACE);
        else
            glDisable(GL_CULL_FACE);
    }
    void setFrontFace(GLenum mode)
    {
        if (frontFace_ != mode)
            glFrontFace(mode);
        frontFace_ = mode;
    }
    void bindTexture(GLuint unit, GLuint texture, GLenum target = GL_TEXTURE_2D)
    {
        if (textures_[unit] == texture)
            return;
        textures_[unit] = texture;
        glActiveTexture(GL_TEXTURE0 + unit);
        glBindTexture(target, texture);
    }
    void bindMaps(const IblMaps* maps)
    {
        if (maps_ == maps)
            return;
        maps_ = maps;
        const IblTextures textures = maps->textures();
        bindTexture(MeshPass::kDiffuseMapUnit, textures.diffuse);
        bindTexture(MeshPass::kGlossy1MapUnit, textures.glossy1);
        bindTexture(MeshPass::kGlossy2MapUnit, textures.glossy2);
        bindTexture(MeshPass::kMirrorMapUnit, textures.mirror);
        mapSlot = glm::vec2(float(textures.slot), float(textures.slots));
    }
    // The bound maps' slot in their bank (mesh.frag's uMapSlot).
    glm::vec2 mapSlot{0.0f, 1.0f};
    // The mesh.frag variant in use (~0: another program is bound).
    uint32_t variantFeatures = ~0U;
    const MeshPass::Variant* variant = nullptr;

    void bindMaterial(const GpuMaterial* material)
    {
        if (material_ == material)
            return;
        material_ = material;
        glBindBufferBase(GL_UNIFORM_BUFFER, kMaterialBlockBinding, material->uniforms.name());
        bindTexture(MeshPass::kBaseColorUnit, material->baseColor);
        bindTexture(MeshPass::kMetallicRoughnessUnit, material->metallicRoughness);
        bindTexture(MeshPass::kNormalUnit, material->normal);
        bindTexture(MeshPass::kEmissiveUnit, material->emissive);
        bindTexture(MeshPass::kSpecularUnit, material->specular);
        bindTexture(MeshPass::kLobeUnit, material->lobe);
        bindTexture(MeshPass::kTangentRotationUnit, material->tangentRotation);
        bindTexture(MeshPass::kOcclusionUnit, material->occlusion);
        bindTexture(MeshPass::kTransmissionUnit, material->transmission);
        setCulling(!material->doubleSided);
    }

private:
    int culling_ = -1; // unknown at the start of a pass
    GLenum frontFace_ = 0;
    std::array<GLuint, 16> textures_{};
    const GpuMaterial* material_ = nullptr;
    const IblMaps* maps_ = nullptr;
};

MeshPass::MeshPass()
    : phantomProgram_(linkProgram(kPhantomProgram)),
      phantomCameraFromMeshLocation_(uniformLocation(phantomProgram_, "uCameraFromMesh")),
      phantomNormalFromMeshLocation_(uniformLocation(phantomProgram_, "uNormalFromMesh")),
      phantomFrameCameraFromViewLocation_(uniformLocation(phantomProgram_, "uFrameCameraFromView")),
      phantomClipFromFrameCameraLocation_(uniformLocation(phantomProgram_, "uClipFromFrameCamera")),
      phantomInverseExposureLocation_(uniformLocation(phantomProgram_, "uInverseExposure")),
      depthOnly_(linkProgram(kDepthOnlyProgram)),
      depthOnlyCameraFromMeshLocation_(uniformLocation(depthOnly_, "uCameraFromMesh")),
      frameUniforms_(GlBuffer::create()), levelZero_(GlSampler::create())
{
    glSamplerParameteri(levelZero_.name(), GL_TEXTURE_MIN_FILTER, GL_LINEAR);
    glSamplerParameteri(levelZero_.name(), GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    glSamplerParameteri(levelZero_.name(), GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    glSamplerParameteri(levelZero_.name(), GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    bindUniformBlock(depthOnly_, "Frame", kFrameBlockBinding);
    glUseProgram(phantomProgram_.name());
    glUniform1i(uniformLocation(phantomProgram_, "uCameraImage"), GLint(kCameraImageUnit));
    glUniform1i(uniformLocation(phantomProgram_, "uCameraDepth"), GLint(kCameraDepthUnit));
    glUniform1i(uniformLocation(phantomProgram_, "uDiffuseMap"), GLint(kDiffuseMapUnit));
    glUniform1i(uniformLocation(phantomProgram_, "uGlossy1Map"), GLint(kGlossy1MapUnit));
    glUniform1i(uniformLocation(phantomProgram_, "uGlossy2Map"), GLint(kGlossy2MapUnit));
    glUniform1i(uniformLocation(phantomProgram_, "uMirrorMap"), GLint(kMirrorMapUnit));
    bindUniformBlock(phantomProgram_, "Frame", kFrameBlockBinding);
    bindUniformBlock(phantomProgram_, "Material", kMaterialBlockBinding);

    glBindBuffer(GL_UNIFORM_BUFFER, frameUniforms_.name());
    glBufferData(GL_UNIFORM_BUFFER, sizeof(FrameUniforms), nullptr, GL_DYNAMIC_DRAW);
    checkGlError("creating the mesh pass");
}

namespace {
// The units of the four environment maps (levelZero_).
constexpr GLuint kMapUnits[] = {MeshPass::kDiffuseMapUnit, MeshPass::kGlossy1MapUnit, MeshPass::kGlossy2MapUnit,
                                MeshPass::kMirrorMapUnit};
} // namespace

const MeshPass::Variant& MeshPass::variant(uint32_t features) const
{
    const auto found = variants_.find(features);
    if (found != variants_.end())
        return found->second;
    Variant variant;
    variant.program = linkProgram(kMeshProgram, meshVariantDefines(features));
    const GlProgram& program = variant.program;
    variant.cameraFromMeshLocation = uniformLocation(program, "uCameraFromMesh");
    // Unlit variants read no normal (-1: glUniform ignores it).
    variant.normalFromMeshLocation = optionalUniformLocation(program, "uNormalFromMesh");
    variant.mapSlotLocation = optionalUniformLocation(program, "uMapSlot");
    glUseProgram(program.name());
    // A variant has only the samplers its features read.
    const std::pair<const char*, GLuint> samplers[] = {{"uBaseColor", kBaseColorUnit},
                                                       {"uMetallicRoughness", kMetallicRoughnessUnit},
                                                       {"uNormal", kNormalUnit},
                                                       {"uEmissive", kEmissiveUnit},
                                                       {"uSpecular", kSpecularUnit},
                                                       {"uLobe", kLobeUnit},
                                                       {"uTangentRotation", kTangentRotationUnit},
                                                       {"uDiffuseMap", kDiffuseMapUnit},
                                                       {"uGlossy1Map", kGlossy1MapUnit},
                                                       {"uGlossy2Map", kGlossy2MapUnit},
                                                       {"uMirrorMap", kMirrorMapUnit},
                                                       {"uShadowMap", kShadowMapUnit},
                                                       {"uOcclusion", kOcclusionUnit},
                                                       {"uTransmission", kTransmissionUnit}};
    for (const auto& [name, unit] : samplers) {
        const GLint location = optionalUniformLocation(program, name);
        if (location >= 0)
            glUniform1i(location, GLint(unit));
    }
    bindUniformBlock(program, "Frame", kFrameBlockBinding);
    bindUniformBlock(program, "Material", kMaterialBlockBinding);
    checkGlError("linking a variant of the mesh program");
    return variants_.emplace(features, std::move(variant)).first->second;
}

void MeshPass::draw(const FrameUniforms& frame, const std::vector<GpuModel>& models, std::span<const DrawItem> items,
                    std::span<const IblMaps* const> maps, int skip, Phantoms phantoms, Detail detail,
                    double focalPixels, const PhantomCamera* camera) const
{
    if (items.empty())
        return;
    glBindBuffer(GL_UNIFORM_BUFFER, frameUniforms_.name());
    glBufferSubData(GL_UNIFORM_BUFFER, 0, sizeof(FrameUniforms), &frame);
    viewFeatures_ = viewFeatures(frame);
    glBindBufferBase(GL_UNIFORM_BUFFER, kFrameBlockBinding, frameUniforms_.name());
    glActiveTexture(GL_TEXTURE0 + kShadowMapUnit);
    glBindTexture(GL_TEXTURE_2D, shadowMap_);

    for (const GLuint unit : kMapUnits)
        glBindSampler(unit, levelZero_.name());

    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_LESS);
    glDepthMask(GL_TRUE);
    // What primitives without vertex colours or a second uv set read (their attribute
    // arrays stay disabled): white and (0, 0). Context state, so set for every pass.
    glVertexAttrib4f(4, 1.0f, 1.0f, 1.0f, 1.0f);
    glVertexAttrib4f(5, 0.0f, 0.0f, 0.0f, 1.0f);
    if (phantoms == Phantoms::DepthOnly) {
        // The phantoms first, into depth alone with a shader that shades nothing.
        // The program writes no colour, which leaves the colour buffer undefined where it
        // draws unless colour writes are off.
        StateCache state;
        glUseProgram(depthOnly_.name());
        glColorMask(GL_FALSE, GL_FALSE, GL_FALSE, GL_FALSE);
        for (size_t i = 0; i < items.size(); ++i)
            if (int(i) != skip && items[i].phantom && !items[i].receiverOnly)
                drawItem(items[i], nullptr, models, state, depthOnlyCameraFromMeshLocation_, -1, detail, focalPixels);
        glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
    }
    // Nearest first: the depth test then rejects hidden fragments before they are shaded.
    // Phantoms carrying the camera image come last, with their own program: they are mostly
    // large surfaces behind and below the objects (a table), whose hidden texels the depth
    // test then skips.
    const bool cameraPhantoms = phantoms == Phantoms::Shaded && camera != nullptr;
    order_.clear();
    for (size_t i = 0; i < items.size(); ++i)
        if (int(i) != skip && !items[i].receiverOnly && (phantoms == Phantoms::Shaded || !items[i].phantom) &&
            !(cameraPhantoms && items[i].phantom))
            order_.push_back({centreDepth(items[i], models), i});
    std::sort(order_.begin(), order_.end());
    StateCache state;
    blended_.clear();
    for (const auto& [depth, i] : order_)
        drawItem(items[i], maps[i], models, state, -1, -1, detail, focalPixels, &blended_, i, true);
    if (cameraPhantoms)
        drawCameraPhantoms(*camera, models, items, maps, skip, state, detail, focalPixels);
    if (transparentStart_)
        transparentStart_();
    if (!blended_.empty()) {
        const bool rgbmMap = frame.frameParams.y > 0.5f && frame.frameParams.z > 0.5f;
        drawBlended(items, maps, models, state, !rgbmMap);
    }
    glBindVertexArray(0);
    for (const GLuint unit : kMapUnits)
        glBindSampler(unit, 0);
}

void MeshPass::drawBlended(std::span<const DrawItem> items, std::span<const IblMaps* const> maps,
                           const std::vector<GpuModel>& models, StateCache& state, bool canBlend) const
{
    // Farthest first (the camera looks along +z).
    std::sort(blended_.begin(), blended_.end(),
              [](const BlendedPrimitive& a, const BlendedPrimitive& b) { return a.depth > b.depth; });
    if (canBlend) {
        // The destination's alpha is kept: the frame's alpha is not coverage.
        glBlendFuncSeparate(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA, GL_ZERO, GL_ONE);
        glDepthMask(GL_FALSE);
    }
    bool blending = false;
    for (const BlendedPrimitive& b : blended_) {
        const GpuModel& model = models[size_t(items[b.item].model)];
        // Glass that is not BLEND too covers what lies behind it: the light through comes
        // from its maps, not from the framebuffer (and an RGBM radiance target keeps its
        // encoding's scale in alpha, which blending would not write).
        const bool blend = canBlend && model.materials[b.primitive->material].alphaMode == GltfAlphaMode::Blend;
        if (blend != blending) {
            if (blend)
                glEnable(GL_BLEND);
            else
                glDisable(GL_BLEND);
            blending = blend;
            if (blendingHook_)
                blendingHook_(blend);
        }
        state.bindMaps(maps[b.item]);
        drawPrimitive(items[b.item], model, *b.primitive, state, -1, -1, true);
    }
    if (blending) {
        glDisable(GL_BLEND);
        if (blendingHook_)
            blendingHook_(false);
    }
    if (canBlend)
        glDepthMask(GL_TRUE);
}

void MeshPass::drawCameraPhantoms(const PhantomCamera& camera, const std::vector<GpuModel>& models,
                                  std::span<const DrawItem> items, std::span<const IblMaps* const> maps, int skip,
                                  StateCache& state, Detail detail, double focalPixels) const
{
    bool bound = false;
    for (size_t i = 0; i < items.size(); ++i) {
        if (int(i) == skip || !items[i].phantom || items[i].receiverOnly)
            continue;
        if (!bound) {
            state.variantFeatures = ~0U;
            glUseProgram(phantomProgram_.name());
            glUniformMatrix4fv(phantomFrameCameraFromViewLocation_, 1, GL_FALSE,
                               glm::value_ptr(camera.frameCameraFromView));
            glUniformMatrix4fv(phantomClipFromFrameCameraLocation_, 1, GL_FALSE,
                               glm::value_ptr(camera.clipFromFrameCamera));
            glUniform1f(phantomInverseExposureLocation_, 1.0f / camera.exposure);
            state.bindTexture(kCameraImageUnit, camera.image);
            state.bindTexture(kCameraDepthUnit, camera.depth);
            bound = true;
        }
        drawItem(items[i], maps[i], models, state, phantomCameraFromMeshLocation_, phantomNormalFromMeshLocation_,
                 detail, focalPixels);
    }
}

double MeshPass::centreDepth(const DrawItem& item, const std::vector<GpuModel>& models)
{
    const GpuModel& model = models[size_t(item.model)];
    const glm::dvec3 centre = 0.5 * (glm::dvec3(model.boundsMin) + glm::dvec3(model.boundsMax));
    return (item.cameraFromModel * glm::dvec4(centre, 1.0)).z;
}

double MeshPass::modelPixels(const DrawItem& item, const GpuModel& model, double focalPixels)
{
    const glm::dvec3 extent = glm::dvec3(model.boundsMax) - glm::dvec3(model.boundsMin);
    const glm::dmat3 linear(item.cameraFromModel);
    const double scale = std::max({glm::length(linear[0]), glm::length(linear[1]), glm::length(linear[2])});
    const glm::dvec3 centre = 0.5 * (glm::dvec3(model.boundsMin) + glm::dvec3(model.boundsMax));
    const double distance = glm::length(glm::dvec3(item.cameraFromModel * glm::dvec4(centre, 1.0)));
    if (distance <= 0.5 * scale * glm::length(extent))
        return std::numeric_limits<double>::infinity();
    return focalPixels * scale * std::max({extent.x, extent.y, extent.z}) / distance;
}

void MeshPass::drawItem(const DrawItem& item, const IblMaps* maps, const std::vector<GpuModel>& models,
                        StateCache& state, GLint cameraFromMeshLocation, GLint normalFromMeshLocation, Detail detail,
                        double focalPixels, std::vector<BlendedPrimitive>* blended, size_t itemIndex,
                        bool variants) const
{
    const bool shaded = variants || normalFromMeshLocation >= 0;
    if (shaded)
        state.bindMaps(maps);
    const GpuModel& model = models[size_t(item.model)];
    const double pixels = focalPixels > 0.0 ? modelPixels(item, model, focalPixels) : 0.0;
    const std::vector<GpuPrimitive>& primitives =
        detail == Detail::Proxy ? proxyLevelFor(model, pixels).primitives : framePrimitivesFor(model, pixels);
    for (const GpuPrimitive& primitive : primitives) {
        const GpuMaterial& material = model.materials[primitive.material];
        // Glass too: it shows what its maps hold behind it, and blended ones behind it must
        // already be drawn for the frame to be sorted.
        if (blended != nullptr && isTransparent(material)) {
            const glm::dvec4 centre =
                item.cameraFromModel * primitive.modelFromMesh *
                glm::dvec4(0.5 * (glm::dvec3(primitive.boundsMin) + glm::dvec3(primitive.boundsMax)), 1.0);
            blended->push_back({centre.z, itemIndex, &primitive});
            continue;
        }
        drawPrimitive(item, model, primitive, state, cameraFromMeshLocation, normalFromMeshLocation, variants);
    }
}

void MeshPass::drawPrimitive(const DrawItem& item, const GpuModel& model, const GpuPrimitive& primitive,
                             StateCache& state, GLint cameraFromMeshLocation, GLint normalFromMeshLocation,
                             bool variants) const
{
    const bool shaded = variants || normalFromMeshLocation >= 0;
    // Composed in double precision: model matrices may carry large translations.
    const glm::dmat4 cameraFromMesh = item.cameraFromModel * primitive.modelFromMesh;
    const glm::dmat3 linear(cameraFromMesh);
    const double determinant = glm::determinant(linear);
    if (determinant == 0.0 || !std::isfinite(determinant))
        return; // flattened to nothing: invisible
    // A mirroring transform turns the winding around (see clipFromCamera for CW).
    state.setFrontFace(determinant > 0.0 ? GL_CW : GL_CCW);
    if (variants) {
        const uint32_t features = model.materials[primitive.material].features | viewFeatures_ |
                                  (primitive.extras.name() != 0 ? mesh_feature::kVertexExtras : 0U);
        if (state.variantFeatures != features) {
            state.variant = &variant(features);
            state.variantFeatures = features;
            glUseProgram(state.variant->program.name());
        }
        cameraFromMeshLocation = state.variant->cameraFromMeshLocation;
        normalFromMeshLocation = state.variant->normalFromMeshLocation;
        glUniform2f(state.variant->mapSlotLocation, state.mapSlot.x, state.mapSlot.y);
    }
    const glm::mat4 cameraFromMeshF(cameraFromMesh);
    glUniformMatrix4fv(cameraFromMeshLocation, 1, GL_FALSE, glm::value_ptr(cameraFromMeshF));
    if (shaded) {
        const glm::mat3 normalFromMesh(glm::transpose(glm::inverse(linear)));
        glUniformMatrix3fv(normalFromMeshLocation, 1, GL_FALSE, glm::value_ptr(normalFromMesh));
        state.bindMaterial(&model.materials[primitive.material]);
    } else {
        state.setCulling(!model.materials[primitive.material].doubleSided);
    }
    glBindVertexArray(primitive.vertexArray.name());
    glDrawElements(GL_TRIANGLES, primitive.indexCount, primitive.indexType, nullptr);
}

} // namespace lumar
