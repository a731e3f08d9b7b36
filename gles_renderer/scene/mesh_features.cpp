#include "gles_renderer/scene/mesh_features.h"

#include <utility>

namespace lumar {

uint32_t viewFeatures(const FrameUniforms& frame)
{
    uint32_t features = 0;
    if (frame.lightDirection.w > 0.5f)
        features |= mesh_feature::kShadow;
    if (frame.frameParams.z > 0.5f)
        features |= mesh_feature::kRgbmMaps;
    if (frame.frameParams.y > 0.5f)
        features |= mesh_feature::kWritesRadiance;
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
        {mesh_feature::kShadow, "HAS_SHADOW"},
        {mesh_feature::kRgbmMaps, "MAPS_RGBM"},
        {mesh_feature::kWritesRadiance, "WRITES_RADIANCE"},
    };
    std::string defines;
    for (const auto& [bit, macro] : kMacros)
        defines += std::string("#define ") + macro + ((features & bit) != 0 ? " true\n" : " false\n");
    const char* alphaMode = (features & mesh_feature::kAlphaBlend) != 0  ? "2.0"
                            : (features & mesh_feature::kAlphaMask) != 0 ? "1.0"
                                                                         : "0.0";
    defines += std::string("#define ALPHA_MODE ") + alphaMode + "\n";
    return defines;
}

} // namespace lumar
