#include "gles_renderer/gltf_materials.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <utility>

#include "core/error.h"
#include "core/log.h"
#include "gles_renderer/rgba8_conversion.h"

namespace lumar::gltf {
namespace {

double finiteOr(double value, double fallback)
{
    return std::isfinite(value) ? value : fallback;
}

template <int N>
glm::vec<N, float> vectorFactor(const std::vector<double>& values, const glm::vec<N, float>& fallback,
                                const std::string& what)
{
    if (values.empty()) {
        return fallback;
    }
    if (values.size() != size_t(N)) {
        throw InputError(what + " has " + std::to_string(values.size()) + " numbers, expected " + std::to_string(N));
    }
    glm::vec<N, float> out;
    for (int i = 0; i < N; ++i) {
        if (!std::isfinite(values[size_t(i)])) {
            throw InputError(what + " holds a non-finite number");
        }
        out[i] = float(values[size_t(i)]);
    }
    return out;
}

// Builds lumar textures on demand, one per (image, colour space) pair actually used.
class TextureTable {
public:
    TextureTable(const tinygltf::Model& model, const std::string& fileForLog) : model_(model), file_(fileForLog) {}

    // Index into textures() for glTF texture `textureIndex` (-1: none), or -1 when the
    // texture has no usable image.
    int resolve(int textureIndex, int texCoord, bool srgb, const std::string& what)
    {
        if (textureIndex < 0) {
            return -1;
        }
        if (size_t(textureIndex) >= model_.textures.size()) {
            throw InputError(what + ": texture " + std::to_string(textureIndex) + " does not exist");
        }
        if (texCoord != 0) {
            LUMAR_LOG(Render, Warn) << file_ << ": " << what << " uses TEXCOORD_" << texCoord
                                    << "; only TEXCOORD_0 is loaded, so it is sampled with that";
        }
        const int imageIndex = model_.textures[size_t(textureIndex)].source;
        if (imageIndex < 0) {
            LUMAR_LOG(Render, Warn) << file_ << ": " << what << ": texture " << textureIndex
                                    << " has no image lumar can read (an image extension?); ignored";
            return -1;
        }
        if (size_t(imageIndex) >= model_.images.size()) {
            throw InputError(what + ": texture " + std::to_string(textureIndex) + " uses image " +
                             std::to_string(imageIndex) + ", which does not exist");
        }
        const auto key = std::make_pair(imageIndex, srgb);
        if (const auto found = built_.find(key); found != built_.end()) {
            return found->second;
        }
        const tinygltf::Image& image = model_.images[size_t(imageIndex)];
        int index = -1;
        if (image.image.empty()) {
            LUMAR_LOG(Render, Warn) << file_ << ": image " << imageIndex << " (" << image.uri << ") was not loaded; "
                                    << what << " is ignored";
        } else {
            GltfTexture texture;
            try {
                texture.image = convertToRgba8(image.image, image.width, image.height, image.component, image.bits);
            } catch (const InputError& e) {
                throw InputError("image " + std::to_string(imageIndex) + ": " + e.what());
            }
            texture.srgb = srgb;
            index = int(textures_.size());
            textures_.push_back(std::move(texture));
        }
        built_.emplace(key, index);
        return index;
    }

    std::vector<GltfTexture> take() { return std::move(textures_); }

private:
    const tinygltf::Model& model_;
    const std::string& file_;
    std::map<std::pair<int, bool>, int> built_;
    std::vector<GltfTexture> textures_;
};

// KHR_materials_emissive_strength: a factor on emissiveFactor that lets emission exceed 1.
float emissiveStrength(const tinygltf::Material& material, const std::string& what)
{
    const auto extension = material.extensions.find("KHR_materials_emissive_strength");
    if (extension == material.extensions.end() || !extension->second.Has("emissiveStrength")) {
        return 1.0f;
    }
    const tinygltf::Value& strength = extension->second.Get("emissiveStrength");
    if (!strength.IsNumber() || !std::isfinite(strength.GetNumberAsDouble()) || strength.GetNumberAsDouble() < 0.0) {
        throw InputError(what + ": emissiveStrength must be a non-negative number");
    }
    return float(strength.GetNumberAsDouble());
}

} // namespace

ConvertedMaterials convertMaterials(const tinygltf::Model& model, const std::string& fileForLog)
{
    ConvertedMaterials out;
    TextureTable textures(model, fileForLog);
    for (size_t m = 0; m < model.materials.size(); ++m) {
        const tinygltf::Material& source = model.materials[m];
        const tinygltf::PbrMetallicRoughness& pbr = source.pbrMetallicRoughness;
        const std::string what = "material " + std::to_string(m);

        GltfMaterial material;
        material.name = source.name;
        material.baseColorFactor = vectorFactor<4>(pbr.baseColorFactor, glm::vec4(1.0f), what + " baseColorFactor");
        material.metallicFactor = float(std::clamp(finiteOr(pbr.metallicFactor, 1.0), 0.0, 1.0));
        material.roughnessFactor = float(std::clamp(finiteOr(pbr.roughnessFactor, 1.0), 0.0, 1.0));
        material.emissiveFactor = vectorFactor<3>(source.emissiveFactor, glm::vec3(0.0f), what + " emissiveFactor") *
                                  emissiveStrength(source, what);
        material.normalScale = float(finiteOr(source.normalTexture.scale, 1.0));
        material.doubleSided = source.doubleSided;

        material.baseColorTexture = textures.resolve(pbr.baseColorTexture.index, pbr.baseColorTexture.texCoord, true,
                                                     what + " baseColorTexture");
        material.metallicRoughnessTexture =
            textures.resolve(pbr.metallicRoughnessTexture.index, pbr.metallicRoughnessTexture.texCoord, false,
                             what + " metallicRoughnessTexture");
        material.normalTexture =
            textures.resolve(source.normalTexture.index, source.normalTexture.texCoord, false, what + " normalTexture");
        material.emissiveTexture = textures.resolve(source.emissiveTexture.index, source.emissiveTexture.texCoord, true,
                                                    what + " emissiveTexture");
        out.materials.push_back(std::move(material));
    }
    out.textures = textures.take();
    return out;
}

} // namespace lumar::gltf
