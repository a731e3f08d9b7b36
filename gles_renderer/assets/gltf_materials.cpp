#include "gles_renderer/assets/gltf_materials.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <initializer_list>
#include <limits>
#include <map>
#include <optional>
#include <string_view>
#include <tuple>
#include <utility>
#include <vector>

#include "core/error.h"
#include "core/log.h"
#include "gles_renderer/assets/lafortune_material.h"
#include "gles_renderer/assets/rgba8_conversion.h"

namespace lumar::gltf {
namespace {

constexpr const char* kLafortuneExtension = "LUMAR_materials_lafortune";

// A scalar factor: finite (issue 16: 1e300 became float infinity) and, for factors the
// specification bounds, clamped into [lo, hi] as before.
double finiteFactor(double value, double lo, double hi, const std::string& what)
{
    if (!std::isfinite(value)) {
        throw InputError(what + " is not a finite number");
    }
    return std::clamp(value, lo, hi);
}

// glTF 2.0 bounds baseColorFactor and emissiveFactor to [0, 1] per component.
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
        if (values[size_t(i)] < 0.0 || values[size_t(i)] > 1.0) {
            throw InputError(what + " holds " + std::to_string(values[size_t(i)]) + ", outside [0, 1]");
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
        if (texCoord > 1) {
            LUMAR_LOG(Render, Warn) << file_ << ": " << what << " uses TEXCOORD_" << texCoord
                                    << "; lumar loads TEXCOORD_0 and TEXCOORD_1, so it is sampled with TEXCOORD_0";
        }
        const GltfSampler sampler = samplerOf(model_.textures[size_t(textureIndex)].sampler);
        const int imageIndex = imageOf(model_.textures[size_t(textureIndex)]);
        if (imageIndex < 0) {
            LUMAR_LOG(Render, Warn) << file_ << ": " << what << ": texture " << textureIndex
                                    << " has no image lumar can read (an image extension?); ignored";
            return -1;
        }
        if (size_t(imageIndex) >= model_.images.size()) {
            throw InputError(what + ": texture " + std::to_string(textureIndex) + " uses image " +
                             std::to_string(imageIndex) + ", which does not exist");
        }
        const auto key = std::make_tuple(imageIndex, srgb, sampler);
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
            samplers_.push_back(sampler);
        }
        built_.emplace(key, index);
        return index;
    }

    std::vector<GltfTexture> take() { return std::move(textures_); }
    std::vector<GltfSampler> takeSamplers() { return std::move(samplers_); }

private:
    const tinygltf::Model& model_;
    const std::string& file_;
    // The texture's image: its source, or EXT_texture_webp's where the file keeps the WebP
    // image in the extension (a fallback PNG in source is then ignored: WebP is decoded).
    static int imageOf(const tinygltf::Texture& texture)
    {
        const auto webp = texture.extensions.find("EXT_texture_webp");
        if (webp != texture.extensions.end() && webp->second.IsObject() && webp->second.Has("source") &&
            webp->second.Get("source").IsInt()) {
            return webp->second.Get("source").GetNumberAsInt();
        }
        return texture.source;
    }

    // glTF 2.0 §5.26: wrap modes and filters as GL enums; anything else is refused, naming
    // the sampler (a wrong value would silently draw the texture wrapped the wrong way).
    [[nodiscard]] GltfSampler samplerOf(int samplerIndex) const
    {
        GltfSampler out;
        if (samplerIndex < 0) {
            return out;
        }
        const std::string what = "sampler " + std::to_string(samplerIndex);
        if (size_t(samplerIndex) >= model_.samplers.size()) {
            throw InputError(what + " does not exist");
        }
        const tinygltf::Sampler& sampler = model_.samplers[size_t(samplerIndex)];
        const auto wrap = [&](int value, const char* field) {
            if (value != 10497 && value != 33071 && value != 33648) {
                throw InputError(what + ": " + field + " " + std::to_string(value) +
                                 " is not a glTF wrap mode (10497 REPEAT, 33071 CLAMP_TO_EDGE, 33648 "
                                 "MIRRORED_REPEAT)");
            }
            return value;
        };
        out.wrapS = wrap(sampler.wrapS, "wrapS");
        out.wrapT = wrap(sampler.wrapT, "wrapT");
        const int minFilter = sampler.minFilter;
        if (minFilter != -1 && minFilter != 9728 && minFilter != 9729 && !(minFilter >= 9984 && minFilter <= 9987)) {
            throw InputError(what + ": minFilter " + std::to_string(minFilter) +
                             " is not a glTF filter (9728 NEAREST, 9729 LINEAR, 9984..9987 mipmapped)");
        }
        out.minFilter = std::max(minFilter, 0);
        const int magFilter = sampler.magFilter;
        if (magFilter != -1 && magFilter != 9728 && magFilter != 9729) {
            throw InputError(what + ": magFilter " + std::to_string(magFilter) +
                             " is not a glTF filter (9728 NEAREST, 9729 LINEAR)");
        }
        out.magFilter = std::max(magFilter, 0);
        return out;
    }

    std::map<std::tuple<int, bool, GltfSampler>, int> built_;
    std::vector<GltfTexture> textures_;
    std::vector<GltfSampler> samplers_;
};

// A textureInfo's uv set and KHR_texture_transform (offset, rotation, scale, texCoord).
GltfUvTransform uvTransform(int texCoord, const tinygltf::ExtensionMap& extensions, const std::string& what)
{
    GltfUvTransform out;
    out.texCoord = texCoord == 1 ? 1 : 0;
    const auto found = extensions.find("KHR_texture_transform");
    if (found == extensions.end()) {
        return out;
    }
    const std::string where = what + " KHR_texture_transform";
    const tinygltf::Value& t = found->second;
    if (!t.IsObject()) {
        throw InputError(where + ": expected an object");
    }
    const auto pair = [&](const char* field, glm::vec2 fallback) {
        if (!t.Has(field)) {
            return fallback;
        }
        const tinygltf::Value& v = t.Get(field);
        if (!v.IsArray() || v.ArrayLen() != 2 || !v.Get(0).IsNumber() || !v.Get(1).IsNumber() ||
            !(std::abs(v.Get(0).GetNumberAsDouble()) <= 1e6) || !(std::abs(v.Get(1).GetNumberAsDouble()) <= 1e6)) {
            throw InputError(where + " " + field + ": expected 2 numbers within [-1e6, 1e6]");
        }
        return glm::vec2(float(v.Get(0).GetNumberAsDouble()), float(v.Get(1).GetNumberAsDouble()));
    };
    out.offset = pair("offset", out.offset);
    out.scale = pair("scale", out.scale);
    if (t.Has("rotation")) {
        const tinygltf::Value& r = t.Get("rotation");
        if (!r.IsNumber() || !(std::abs(r.GetNumberAsDouble()) <= 1e6)) {
            throw InputError(where + " rotation: expected a number within [-1e6, 1e6]");
        }
        out.rotation = float(r.GetNumberAsDouble());
    }
    if (t.Has("texCoord")) {
        const tinygltf::Value& c = t.Get("texCoord");
        if (!c.IsInt() || c.GetNumberAsInt() < 0) {
            throw InputError(where + " texCoord: expected a non-negative integer");
        }
        out.texCoord = c.GetNumberAsInt() == 1 ? 1 : 0;
    }
    return out;
}

// alphaMode and alphaCutoff (glTF 2.0 §3.9.4), KHR_materials_unlit, occlusion strength.
void readAlphaAndUnlit(const tinygltf::Material& source, const std::string& what, GltfMaterial& material)
{
    if (source.alphaMode == "MASK") {
        material.alphaMode = GltfAlphaMode::Mask;
    } else if (source.alphaMode == "BLEND") {
        material.alphaMode = GltfAlphaMode::Blend;
    } else if (source.alphaMode != "OPAQUE" && !source.alphaMode.empty()) {
        throw InputError(what + " alphaMode \"" + source.alphaMode + "\" is not OPAQUE, MASK or BLEND");
    }
    if (!(source.alphaCutoff >= 0.0 && source.alphaCutoff <= 1e6)) {
        throw InputError(what + " alphaCutoff is not a number within [0, 1e6]");
    }
    material.alphaCutoff = float(source.alphaCutoff);
    material.unlit = source.extensions.count("KHR_materials_unlit") != 0;
    material.occlusionStrength =
        float(finiteFactor(source.occlusionTexture.strength, 0.0, 1.0, what + " occlusionTexture.strength"));
}

// KHR_materials_emissive_strength: a factor on emissiveFactor that lets emission exceed 1.
float emissiveStrength(const tinygltf::Material& material, const std::string& what)
{
    const auto extension = material.extensions.find("KHR_materials_emissive_strength");
    if (extension == material.extensions.end() || !extension->second.Has("emissiveStrength")) {
        return 1.0f;
    }
    const tinygltf::Value& strength = extension->second.Get("emissiveStrength");
    // No bound in the extension; 1e6 keeps factor x strength finite in float.
    constexpr double kMaxEmissiveStrength = 1e6;
    if (!strength.IsNumber() || !std::isfinite(strength.GetNumberAsDouble()) || strength.GetNumberAsDouble() < 0.0 ||
        strength.GetNumberAsDouble() > kMaxEmissiveStrength) {
        throw InputError(what + ": emissiveStrength must be a number within [0, 1e6]");
    }
    return float(strength.GetNumberAsDouble());
}

// "material 3 ("Body")": the index finds it in the file, the name in an editor.
std::string materialLabel(size_t index, const std::string& name)
{
    return "material " + std::to_string(index) + (name.empty() ? " (unnamed)" : " (\"" + name + "\")");
}

std::string formatNumber(double v)
{
    char text[32];
    std::snprintf(text, sizeof text, "%g", v);
    return text;
}

// One number of a Khronos material extension: absent is `fallback`; else a finite number
// within [lo, hi] (`loExclusive`: above lo), or InputError "WHAT FIELD: ...".
float extensionNumber(const tinygltf::Value& extension, const char* field, float fallback, double lo, double hi,
                      bool loExclusive, const std::string& what)
{
    if (!extension.Has(field)) {
        return fallback;
    }
    const tinygltf::Value& value = extension.Get(field);
    if (!value.IsNumber()) {
        throw InputError(what + " " + field + ": expected a number");
    }
    const double v = value.GetNumberAsDouble();
    if (!std::isfinite(v) || (loExclusive ? v <= lo : v < lo) || v > hi) {
        throw InputError(what + " " + field + ": " + formatNumber(v) + " is outside " + (loExclusive ? "(" : "[") +
                         formatNumber(lo) + ", " + formatNumber(hi) + "]");
    }
    return float(v);
}

// The extension object `name` of `material`, or null; InputError when it is not an object.
const tinygltf::Value* materialExtension(const tinygltf::Material& material, const char* name, const std::string& what)
{
    const auto found = material.extensions.find(name);
    if (found == material.extensions.end()) {
        return nullptr;
    }
    if (!found->second.IsObject()) {
        throw InputError(what + " " + name + ": expected an object");
    }
    return &found->second;
}

// A textureInfo object inside a material extension (tinygltf leaves those as raw values):
// its index resolved as a linear texture, its uv set and transform into `transform`.
int extensionTexture(const tinygltf::Value& info, const std::string& field, TextureTable& textures,
                     GltfUvTransform& transform)
{
    if (!info.IsObject() || !info.Has("index") || !info.Get("index").IsInt() ||
        info.Get("index").GetNumberAsInt() < 0) {
        throw InputError(field + ": expected a textureInfo object with a non-negative index");
    }
    int texCoord = 0;
    if (info.Has("texCoord")) {
        if (!info.Get("texCoord").IsInt() || info.Get("texCoord").GetNumberAsInt() < 0) {
            throw InputError(field + " texCoord: expected a non-negative integer");
        }
        texCoord = info.Get("texCoord").GetNumberAsInt();
    }
    tinygltf::ExtensionMap extensions;
    if (info.Has("extensions") && info.Get("extensions").IsObject()) {
        for (const std::string& key : info.Get("extensions").Keys()) {
            extensions[key] = info.Get("extensions").Get(key);
        }
    }
    transform = uvTransform(texCoord, extensions, field);
    return textures.resolve(info.Get("index").GetNumberAsInt(), texCoord, false, field);
}

// KHR_materials_transmission (factor, texture), KHR_materials_ior and KHR_materials_volume
// (thickness, attenuation). Ranges are the extensions' own; bounds the specifications leave
// open are 1e6 (model units), beyond which float arithmetic in the shader overflows.
void readTransmission(const tinygltf::Material& source, const std::string& what, GltfMaterial& material,
                      TextureTable& textures)
{
    GltfTransmission& t = material.transmission;
    t.tint = glm::vec3(material.baseColorFactor);
    if (const tinygltf::Value* e = materialExtension(source, "KHR_materials_transmission", what)) {
        const std::string where = what + " KHR_materials_transmission";
        t.factor = extensionNumber(*e, "transmissionFactor", 0.0f, 0.0, 1.0, false, where);
        if (e->Has("transmissionTexture")) {
            t.texture = extensionTexture(e->Get("transmissionTexture"), where + " transmissionTexture", textures,
                                         t.uvTransform);
        }
    }
    if (const tinygltf::Value* e = materialExtension(source, "KHR_materials_ior", what)) {
        const std::string where = what + " KHR_materials_ior";
        // The schema allows ior >= 1 or exactly 0 (full reflectance, kept from
        // KHR_materials_pbrSpecularGlossiness); anything in between is no material.
        t.ior = extensionNumber(*e, "ior", 1.5f, 0.0, 1e6, false, where);
        if (t.ior != 0.0f && t.ior < 1.0f) {
            throw InputError(where + " ior: " + formatNumber(t.ior) +
                             " is below 1 (only 0, the extension's special value, may be)");
        }
    }
    if (const tinygltf::Value* e = materialExtension(source, "KHR_materials_volume", what)) {
        const std::string where = what + " KHR_materials_volume";
        t.thickness = extensionNumber(*e, "thicknessFactor", 0.0f, 0.0, 1e6, false, where);
        if (e->Has("thicknessTexture")) {
            GltfUvTransform unused; // the mean over the texture is used (volumeThickness)
            t.thicknessTexture =
                extensionTexture(e->Get("thicknessTexture"), where + " thicknessTexture", textures, unused);
        }
        t.attenuationDistance = extensionNumber(*e, "attenuationDistance", std::numeric_limits<float>::infinity(), 0.0,
                                                std::numeric_limits<double>::infinity(), true, where);
        if (e->Has("attenuationColor")) {
            const tinygltf::Value& c = e->Get("attenuationColor");
            if (!c.IsArray() || c.ArrayLen() != 3) {
                throw InputError(where + " attenuationColor: expected 3 numbers within [0, 1]");
            }
            std::vector<double> values;
            for (int i = 0; i < 3; ++i) {
                values.push_back(c.Get(i).IsNumber() ? c.Get(i).GetNumberAsDouble() : std::nan(""));
            }
            t.attenuationColor = vectorFactor<3>(values, glm::vec3(1.0f), where + " attenuationColor");
        }
    }
}

// Typed access to the fields of one LUMAR_materials_lafortune object (see
// LUMAR_materials_lafortune.md). tinygltf drops JSON nulls, empty arrays and empty objects
// while parsing, so those read as absent fields.
class LafortuneExtensionReader {
public:
    LafortuneExtensionReader(const tinygltf::Value& object, std::string prefix)
        : object_(object), prefix_(std::move(prefix))
    {
    }

    [[nodiscard]] std::string what(std::string_view field) const { return prefix_ + std::string(field); }
    [[noreturn]] void fail(std::string_view field, const std::string& message) const
    {
        throw InputError(what(field) + ": " + message);
    }

    void rejectUnknownFields(std::initializer_list<std::string_view> known) const
    {
        for (const std::string& key : object_.Keys()) {
            if (key != "extensions" && key != "extras" && std::find(known.begin(), known.end(), key) == known.end()) {
                fail(key, "unknown field");
            }
        }
    }

    std::optional<float> number(std::string_view field, double min, double max, bool maxExclusive) const
    {
        const std::string key(field);
        if (!object_.Has(key)) {
            return std::nullopt;
        }
        const tinygltf::Value& value = object_.Get(key);
        if (!value.IsNumber()) {
            fail(field, "expected a number");
        }
        const double v = value.GetNumberAsDouble();
        if (!std::isfinite(v) || v < min || (maxExclusive ? v >= max : v > max)) {
            fail(field, formatNumber(v) + " is outside [" + formatNumber(min) + ", " + formatNumber(max) +
                            (maxExclusive ? ")" : "]"));
        }
        return float(v);
    }

    std::optional<glm::vec3> vec3(std::string_view field, double min, double max) const
    {
        const std::string key(field);
        if (!object_.Has(key)) {
            return std::nullopt;
        }
        const tinygltf::Value& value = object_.Get(key);
        const std::string expected =
            "expected an array of 3 numbers within [" + formatNumber(min) + ", " + formatNumber(max) + "]";
        if (!value.IsArray() || value.ArrayLen() != 3) {
            fail(field, expected + (value.IsArray() ? ", found " + std::to_string(value.ArrayLen()) : ""));
        }
        glm::vec3 out;
        for (int i = 0; i < 3; ++i) {
            const tinygltf::Value& element = value.Get(i);
            if (!element.IsNumber() || !std::isfinite(element.GetNumberAsDouble()) ||
                element.GetNumberAsDouble() < min || element.GetNumberAsDouble() > max) {
                fail(field, expected);
            }
            out[i] = float(element.GetNumberAsDouble());
        }
        return out;
    }

    struct TextureInfo {
        int index = -1;
        int texCoord = 0;
    };

    // A glTF textureInfo object: {"index": N, "texCoord": M}; the index is checked later.
    std::optional<TextureInfo> texture(std::string_view field) const
    {
        const std::string key(field);
        if (!object_.Has(key)) {
            return std::nullopt;
        }
        const tinygltf::Value& value = object_.Get(key);
        if (!value.IsObject()) {
            fail(field, "expected a textureInfo object {\"index\": N}");
        }
        for (const std::string& member : value.Keys()) {
            if (member != "index" && member != "texCoord" && member != "extensions" && member != "extras") {
                fail(field, "unknown field " + member);
            }
        }
        TextureInfo info;
        if (!value.Has("index")) {
            fail(field, "index is missing");
        }
        if (!value.Get("index").IsInt() || value.Get("index").GetNumberAsInt() < 0) {
            fail(field, "index must be a non-negative integer");
        }
        info.index = value.Get("index").GetNumberAsInt();
        if (value.Has("texCoord")) {
            if (!value.Get("texCoord").IsInt() || value.Get("texCoord").GetNumberAsInt() < 0) {
                fail(field, "texCoord must be a non-negative integer");
            }
            info.texCoord = value.Get("texCoord").GetNumberAsInt();
        }
        return info;
    }

private:
    const tinygltf::Value& object_;
    std::string prefix_;
};

// LUMAR_materials_lafortune: the full Lafortune parameter set; every field absent falls back
// to the metallic-roughness conversion of the material's own factors.
void readLafortuneExtension(const tinygltf::Value& extension, const std::string& label, GltfMaterial& material,
                            TextureTable& textures)
{
    if (!extension.IsObject()) {
        throw InputError(label + " " + kLafortuneExtension + ": expected an object");
    }
    const LafortuneExtensionReader r(extension, label + " " + std::string(kLafortuneExtension) + ".");
    r.rejectUnknownFields({"diffuseFactor", "diffuseTexture", "specularFactor", "specularTexture", "lobeFactor",
                           "exponentFactor", "lobeTexture", "fresnelPhi", "tangentRotation", "tangentRotationTexture"});

    LafortuneParams p = lafortuneFromMetallicRoughness(glm::vec3(material.baseColorFactor), material.metallicFactor,
                                                       material.roughnessFactor);
    p.diffuse = r.vec3("diffuseFactor", 0.0, 1.0).value_or(p.diffuse);
    p.specular = r.vec3("specularFactor", 0.0, 1.0).value_or(p.specular);
    p.lobe = r.vec3("lobeFactor", -kMaxLobeCoefficient, kMaxLobeCoefficient).value_or(p.lobe);
    if (p.lobe == glm::vec3(0.0f)) {
        r.fail("lobeFactor", "all three coefficients are 0: the lobe has no direction");
    }
    p.exponent = r.number("exponentFactor", kMinLafortuneExponent, kMaxLafortuneExponent, false).value_or(p.exponent);
    p.fresnelPhi = r.number("fresnelPhi", 0.0, 1.0, true).value_or(p.fresnelPhi);
    const std::optional<float> rotation = r.number("tangentRotation", 0.0, 1.0, false);

    const auto resolve = [&](std::string_view field, bool srgb, int current, GltfTextureSlot slot) {
        const auto info = r.texture(field);
        if (info) {
            material.uvTransforms[size_t(slot)] = GltfUvTransform{};
            material.uvTransforms[size_t(slot)].texCoord = info->texCoord == 1 ? 1 : 0;
        }
        return info ? textures.resolve(info->index, info->texCoord, srgb, r.what(field)) : current;
    };
    // rho_d's texture takes the base-colour slot: the shader multiplies the same sRGB texel
    // by rho_d instead of by the base colour.
    material.baseColorTexture = resolve("diffuseTexture", true, material.baseColorTexture, GltfTextureSlot::BaseColor);
    material.specularTexture = resolve("specularTexture", true, -1, GltfTextureSlot::Specular);
    material.lobeTexture = resolve("lobeTexture", false, -1, GltfTextureSlot::Lobe);
    material.tangentRotationTexture = resolve("tangentRotationTexture", false, -1, GltfTextureSlot::TangentRotation);
    // The rotation is factor x texel; the conversion's factor 0 would hide the texture, so a
    // rotation texture without a factor gets 1.
    p.tangentRotation = rotation.value_or(material.tangentRotationTexture >= 0 ? 1.0f : 0.0f);

    material.lafortune = p;
    material.hasLafortune = true;
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
        material.metallicFactor = float(finiteFactor(pbr.metallicFactor, 0.0, 1.0, what + " metallicFactor"));
        material.roughnessFactor = float(finiteFactor(pbr.roughnessFactor, 0.0, 1.0, what + " roughnessFactor"));
        material.emissiveFactor = vectorFactor<3>(source.emissiveFactor, glm::vec3(0.0f), what + " emissiveFactor") *
                                  emissiveStrength(source, what);
        // No bound in the specification; beyond 1e6 the float would overflow in the shader.
        if (!(std::abs(source.normalTexture.scale) <= 1e6)) {
            throw InputError(what + " normalTexture.scale is not a number within [-1e6, 1e6]");
        }
        material.normalScale = float(source.normalTexture.scale);
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
        material.occlusionTexture = textures.resolve(source.occlusionTexture.index, source.occlusionTexture.texCoord,
                                                     false, what + " occlusionTexture");
        const auto slot = [&](GltfTextureSlot s) -> GltfUvTransform& { return material.uvTransforms[size_t(s)]; };
        slot(GltfTextureSlot::BaseColor) =
            uvTransform(pbr.baseColorTexture.texCoord, pbr.baseColorTexture.extensions, what + " baseColorTexture");
        slot(GltfTextureSlot::MetallicRoughness) =
            uvTransform(pbr.metallicRoughnessTexture.texCoord, pbr.metallicRoughnessTexture.extensions,
                        what + " metallicRoughnessTexture");
        slot(GltfTextureSlot::Normal) =
            uvTransform(source.normalTexture.texCoord, source.normalTexture.extensions, what + " normalTexture");
        slot(GltfTextureSlot::Emissive) =
            uvTransform(source.emissiveTexture.texCoord, source.emissiveTexture.extensions, what + " emissiveTexture");
        slot(GltfTextureSlot::Occlusion) = uvTransform(source.occlusionTexture.texCoord,
                                                       source.occlusionTexture.extensions, what + " occlusionTexture");
        readAlphaAndUnlit(source, what, material);
        readTransmission(source, what, material, textures);
        if (const auto lafortune = source.extensions.find(kLafortuneExtension); lafortune != source.extensions.end()) {
            readLafortuneExtension(lafortune->second, materialLabel(m, source.name), material, textures);
        }
        out.materials.push_back(std::move(material));
    }
    out.textures = textures.take();
    out.samplers = textures.takeSamplers();
    return out;
}

} // namespace lumar::gltf
