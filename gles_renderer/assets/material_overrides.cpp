#include "gles_renderer/assets/material_overrides.h"

#include <algorithm>
#include <map>
#include <string_view>
#include <vector>

#include "core/error.h"
#include "gles_renderer/assets/lafortune_material.h"

namespace lumar {
namespace {

std::string quoteName(std::string_view name)
{
    return "\"" + std::string(name) + "\"";
}

std::string materialNameList(const GltfModel& model)
{
    std::string list;
    std::vector<std::string_view> listed;
    for (const GltfMaterial& material : model.materials) {
        if (!material.name.empty() && std::find(listed.begin(), listed.end(), material.name) == listed.end()) {
            listed.push_back(material.name);
            list += (list.empty() ? "" : ", ") + quoteName(material.name);
        }
    }
    return list.empty() ? "it has no named materials" : "its materials: " + list;
}

} // namespace

void applyMaterialOverrides(GltfModel& model, const MaterialOverrides& overrides)
{
    const std::string& fileName = overrides.source;
    // Every check first, so a bad entry leaves the model as it was.
    for (const auto& [name, entry] : overrides.materials) {
        if (name == "*") {
            continue;
        }
        // Captured through a plain reference: clang before 16 cannot capture a structured
        // binding in a lambda (P1091), and Debian 12's clang 14 builds the fuzz targets.
        const std::string& wanted = name;
        const bool found = std::any_of(model.materials.begin(), model.materials.end(),
                                       [&](const GltfMaterial& m) { return m.name == wanted; });
        if (!found) {
            throw InputError(fileName + ":" + std::to_string(entry.line) + ": material " + quoteName(name) +
                             " matches no material of " + model.file.string() + " (" + materialNameList(model) + ")");
        }
    }

    const auto wildcard = overrides.materials.find(std::string_view("*"));
    int swirlTexture = -1;
    std::map<const MaterialOverride*, int> imageTextures;
    const auto appendTexture = [&](Image8 image) {
        GltfTexture texture;
        texture.image = std::move(image);
        texture.srgb = false; // angle data, not colour
        model.textures.push_back(std::move(texture));
        return int(model.textures.size()) - 1;
    };

    for (GltfMaterial& material : model.materials) {
        auto match = overrides.materials.find(std::string_view(material.name));
        if (match == overrides.materials.end()) {
            match = wildcard;
        }
        if (match == overrides.materials.end()) {
            continue;
        }
        const MaterialOverride& entry = match->second;

        // The base the fields override: the preset, else what the material already has.
        const bool ownBase = !entry.preset && material.hasLafortune;
        LafortuneParams p = entry.preset ? *materialPreset(*entry.preset)
                            : material.hasLafortune
                                ? material.lafortune
                                : lafortuneFromMetallicRoughness(glm::vec3(material.baseColorFactor),
                                                                 material.metallicFactor, material.roughnessFactor);
        // A preset says what passes through, too: glass lets light through, chrome none.
        if (entry.preset) {
            material.transmission = materialPresetTransmission(*entry.preset);
        }
        p.diffuse = entry.diffuse.value_or(p.diffuse);
        p.specular = entry.specular.value_or(p.specular);
        p.lobe = entry.lobe.value_or(p.lobe);
        p.exponent = entry.exponent.value_or(p.exponent);
        p.fresnelPhi = entry.fresnelPhi.value_or(p.fresnelPhi);

        bool attached = false;
        switch (entry.rotationTexture) {
        case MaterialOverride::RotationTexture::Unset:
            if (entry.preset && materialPresetUsesSwirlRotation(*entry.preset)) {
                attached = true;
            }
            break;
        case MaterialOverride::RotationTexture::None:
            material.tangentRotationTexture = -1;
            break;
        case MaterialOverride::RotationTexture::Swirl:
            attached = true;
            break;
        case MaterialOverride::RotationTexture::Image: {
            auto [it, added] = imageTextures.emplace(&entry, -1);
            if (added) {
                it->second = appendTexture(entry.rotationImage);
            }
            material.tangentRotationTexture = it->second;
            break;
        }
        }
        if (attached) {
            if (swirlTexture < 0) {
                swirlTexture = appendTexture(makeSwirlRotationTexture(kSwirlRotationTextureSize));
            }
            material.tangentRotationTexture = swirlTexture;
        }
        attached = attached || entry.rotationTexture == MaterialOverride::RotationTexture::Image;
        // The texture's angle is multiplied by the factor, so a texture an override attaches
        // (or one under a base that knew nothing of it) would vanish under a factor of 0.
        if (entry.tangentRotation) {
            p.tangentRotation = *entry.tangentRotation;
        } else if (material.tangentRotationTexture >= 0 && (attached || !ownBase)) {
            p.tangentRotation = 1.0f;
        }

        // The emissive preset lights a material that emits nothing of its own (its light
        // then reaches the lens effects' bright pass); one that emits keeps its own light.
        if (entry.preset && material.emissiveFactor == glm::vec3(0.0f)) {
            material.emissiveFactor = materialPresetEmission(*entry.preset);
        }
        material.lafortune = p;
        material.hasLafortune = true;
    }
}

} // namespace lumar
