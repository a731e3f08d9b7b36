#include "gles_renderer/scene/mesh_features.h"

#include <algorithm>
#include <utility>

namespace lumar {
namespace {

// mesh.frag's IS_LAFORTUNE and HAS_LOBE_TEXTURE, as the generic program reads them.
bool isLafortune(const MaterialUniforms& material)
{
    return material.metallicRoughness.z > 0.5f;
}
bool hasLobeTexture(const MaterialUniforms& material)
{
    return material.textureFlags.z > 0.5f;
}

} // namespace

uint32_t viewFeatures(const FrameUniforms& frame)
{
    uint32_t features = 0;
    if (frame.lightDirection.w > 0.5f)
        features |= mesh_feature::kShadow;
    if (frame.frameParams.z > 0.5f)
        features |= mesh_feature::kRgbmMaps;
    return features;
}

uint32_t glossFeatures(const MaterialUniforms& material)
{
    double exponent = 1.0;
    if (isLafortune(material)) {
        // Lafortune: n = max(factor x the lobe texture's alpha, 1); a texture may lower it.
        if (hasLobeTexture(material))
            return 0;
        exponent = std::max(double(material.lobeFactor.w), 1.0);
    } else {
        // Metallic-roughness as mesh.frag converts it: the texture's roughness only scales
        // the factor down, which raises n.
        const double roughness = std::clamp(double(material.metallicRoughness.y), 0.0, 1.0);
        const double alpha = std::max(roughness * roughness, 1e-4);
        exponent = std::clamp(2.0 / (alpha * alpha) - 2.0, 1.0, 4096.0);
    }
    // s = log2(n) / 12 (lafortune.glsl): 1/4 at n = 8, 1/2 at 64, 1 at 4096. A margin of 1 %
    // below 1/4 and 1/2 keeps a lookup whose weight the shader's float log2 might leave
    // above zero; at 1 the glossy-2 weight is 1 - min(2 s - 1, 1), within 1e-6 of 0.
    if (exponent >= 4096.0)
        return mesh_feature::kGlossMirror;
    if (exponent >= 64.0 * 1.01)
        return mesh_feature::kGlossHalf;
    if (exponent >= 8.0 * 1.01)
        return mesh_feature::kGlossQuarter;
    return 0;
}

uint32_t reflectanceFeatures(const MaterialUniforms& material)
{
    uint32_t features = 0;
    const glm::vec4& colour = material.baseColorFactor;
    if (colour.r != 0.0f || colour.g != 0.0f || colour.b != 0.0f)
        features |= mesh_feature::kDiffuse;
    if (isLafortune(material) && material.specularFactor.w != 0.0f)
        features |= mesh_feature::kTangentRotation;
    if (!isLafortune(material) || (!hasLobeTexture(material) && material.lobeFactor.x == -1.0f &&
                                   material.lobeFactor.y == -1.0f && material.lobeFactor.z == 1.0f))
        features |= mesh_feature::kPhongLobe;
    return features;
}

std::string meshVariantDefines(uint32_t features)
{
    // The macro names of mesh.frag's #ifndef block, bit by bit.
    static constexpr std::pair<uint32_t, const char*> kMacros[] = {
        {mesh_feature::kBaseColorTexture, "HAS_BASE_COLOR_TEXTURE"},
        {mesh_feature::kSecondTexture, "HAS_SECOND_TEXTURE"},
        {mesh_feature::kLobeTexture, "HAS_LOBE_TEXTURE"},
        {mesh_feature::kRotationTexture, "HAS_ROTATION_TEXTURE"},
        {mesh_feature::kLafortune, "IS_LAFORTUNE"},
        {mesh_feature::kNormalMap, "HAS_NORMAL_MAP"},
        {mesh_feature::kEmission, "HAS_EMISSION"},
        {mesh_feature::kOcclusionTexture, "HAS_OCCLUSION_TEXTURE"},
        {mesh_feature::kUnlit, "IS_UNLIT"},
        {mesh_feature::kTransmission, "HAS_TRANSMISSION"},
        {mesh_feature::kDiffuse, "HAS_DIFFUSE"},
        {mesh_feature::kTangentRotation, "HAS_TANGENT_ROTATION"},
        {mesh_feature::kPhongLobe, "PHONG_LOBE"},
        {mesh_feature::kVertexExtras, "HAS_VERTEX_EXTRAS"},
        {mesh_feature::kShadow, "HAS_SHADOW"},
        {mesh_feature::kRgbmMaps, "MAPS_RGBM"},
    };
    std::string defines;
    for (const auto& [bit, macro] : kMacros)
        defines += std::string("#define ") + macro + ((features & bit) != 0 ? " true\n" : " false\n");
    const char* alphaMode = (features & mesh_feature::kAlphaBlend) != 0  ? "2.0"
                            : (features & mesh_feature::kAlphaMask) != 0 ? "1.0"
                                                                         : "0.0";
    defines += std::string("#define ALPHA_MODE ") + alphaMode + "\n";
    // Without a floor mesh.frag's default (0: every map) holds.
    const char* glossFloor = (features & mesh_feature::kGlossMirror) != 0    ? "1.0"
                             : (features & mesh_feature::kGlossHalf) != 0    ? "0.5"
                             : (features & mesh_feature::kGlossQuarter) != 0 ? "0.25"
                                                                             : nullptr;
    if (glossFloor != nullptr)
        defines += std::string("#define GLOSS_FLOOR ") + glossFloor + "\n";
    return defines;
}

} // namespace lumar
