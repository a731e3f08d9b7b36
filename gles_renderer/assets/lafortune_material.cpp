#include "gles_renderer/assets/lafortune_material.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <string>

#include "core/error.h"

namespace lumar {
namespace {

// Largest texture side the renderer uploads (the glTF loader refuses larger images too).
constexpr int kMaxTextureSide = 16384;

struct Preset {
    std::string_view name;
    LafortuneParams params;
    bool swirl;
};

LafortuneParams params(glm::vec3 diffuse, glm::vec3 specular, glm::vec3 lobe, float exponent, float fresnelPhi)
{
    LafortuneParams p;
    p.diffuse = diffuse;
    p.specular = specular;
    p.lobe = lobe;
    p.exponent = exponent;
    p.fresnelPhi = fresnelPhi;
    p.tangentRotation = 0.0f;
    return p;
}

constexpr glm::vec3 kPhongMirrorLobe{-1.0f, -1.0f, 1.0f};

// Reflectances are linear, F0-style values at normal incidence; the Fresnel factor raises
// rho_s towards 1 at grazing angles.
const std::array<Preset, 8> kPresets = {{
    // Polished chrome plating as viewers expect it: a neutral near-mirror. (Bare chromium's
    // F0 is only ~0.55; 0.95 is the look of a chromed bumper or a silvered mirror.) No
    // diffuse term at all, as for every metal; n = the exponent cap, i.e. the mirror map.
    {"chrome",
     params(glm::vec3(0.0f), glm::vec3(0.95f), kPhongMirrorLobe, kMaxLafortuneExponent, kMetallicRoughnessFresnelPhi),
     false},
    // Brushed aluminium (F0 ~ 0.91, 0.92, 0.92; slightly dulled by the brushing). Grooves run
    // along T, so the micro-normals spread across them, along B: |C_y| < |C_x| = C_z.
    // Evaluated against a point light the lobe falls off with the half-vector tilt s as
    // exp(-n s^2 (1 + |C|)/4) per axis, so C_y = -0.8 widens the highlight along B by
    // sqrt(2/1.8) = 5% only (one Lafortune lobe with C_z = 1 cannot exceed sqrt 2). Under
    // environment lighting, as lumar renders it (McAllister), the lobe magnitude
    // |C_v|^n = (1 - s^2 (1 - C_y^2) sin^2 beta)^(n/2) for a view tilted by asin(s) at an angle
    // beta from T does the visible work: with n = 200 it halves at beta = 16 degrees for a 30
    // degree view and at 11 degrees for 45 degrees, so the swirl texture shows the bright
    // bow-tie of a brushed disc while the rest stays dim metal. C_y = -0.6 narrows those
    // wedges to 8-12 degrees and blackens the disc elsewhere; -0.95 widens them to 22-32.
    {"brushed_metal",
     params(glm::vec3(0.0f), glm::vec3(0.85f, 0.86f, 0.87f), glm::vec3(-1.0f, -0.8f, 1.0f), 200.0f,
            kMetallicRoughnessFresnelPhi),
     true},
    // Red automotive paint: a coloured diffuse base (albedo of a saturated red pigment) under
    // a clear lacquer coat (polymer, index ~1.5 -> F0 0.04-0.05) polished to n = 500 with a
    // slightly stronger grazing Fresnel than Schlick (phi 0.2: exponent 4) as clear coats show.
    {"car_paint", params(glm::vec3(0.45f, 0.03f, 0.03f), glm::vec3(0.05f), kPhongMirrorLobe, 500.0f, 0.2f), false},
    // Tyre rubber: carbon-black filled, albedo ~0.04; a faint, very broad sheen (n = 4). Its
    // rough surface smears out the grazing-angle mirror, so a weak Fresnel (phi 0.1: exponent 9).
    {"rubber", params(glm::vec3(0.04f), glm::vec3(0.03f), kPhongMirrorLobe, 4.0f, 0.1f), false},
    // Glossy injection-moulded plastic: white diffuse (the colour comes from the base-colour
    // texture or a diffuse override), dielectric specular slightly above F0 0.04 for a
    // glossy finish, n = 60 (the glossy-2 map range), Schlick Fresnel.
    {"plastic", params(glm::vec3(0.8f), glm::vec3(0.05f), kPhongMirrorLobe, 60.0f, kMetallicRoughnessFresnelPhi),
     false},
    // Clear glass: no diffuse, F0 of index 1.5, a perfect mirror with Schlick's Fresnel. The
    // light through the glass is materialPresetTransmission's, not the BRDF's.
    {"glass",
     params(glm::vec3(0.0f), glm::vec3(kDielectricSpecular), kPhongMirrorLobe, kMaxLafortuneExponent,
            kMetallicRoughnessFresnelPhi),
     false},
    // A pane of clear glass (a window): the same surface as `glass`, but thin-walled
    // (glTF's thickness 0), so the view passes straight through and is not bent as a
    // lens bends it (a 4 mm pane shifts the view sideways by about 1 mm and keeps its
    // direction).
    {"thin_glass",
     params(glm::vec3(0.0f), glm::vec3(kDielectricSpecular), kPhongMirrorLobe, kMaxLafortuneExponent,
            kMetallicRoughnessFresnelPhi),
     false},
    // Lamps and screens: the light itself is glTF's emissiveFactor/emissiveTexture; the surface
    // under it is a dull dark diffuser (albedo 0.1, faint broad specular) so reflections of
    // the environment do not wash the emission out. No Fresnel boost.
    {"emissive", params(glm::vec3(0.1f), glm::vec3(0.02f), kPhongMirrorLobe, 8.0f, 0.0f), false},
}};

const std::array<std::string_view, kPresets.size()> kPresetNames = [] {
    std::array<std::string_view, kPresets.size()> names{};
    for (size_t i = 0; i < kPresets.size(); ++i) {
        names[i] = kPresets[i].name;
    }
    return names;
}();

const Preset* findPreset(std::string_view name)
{
    const auto found = std::find_if(kPresets.begin(), kPresets.end(), [&](const Preset& p) { return p.name == name; });
    return found == kPresets.end() ? nullptr : &*found;
}

} // namespace

LafortuneParams lafortuneFromMetallicRoughness(glm::vec3 baseColor, float metallic, float roughness)
{
    const glm::vec3 base = glm::clamp(baseColor, 0.0f, 1.0f);
    const float m = std::clamp(metallic, 0.0f, 1.0f);
    const float r = std::clamp(roughness, 0.0f, 1.0f);

    LafortuneParams p;
    p.diffuse = base * (1.0f - m);
    p.specular = glm::mix(glm::vec3(kDielectricSpecular), base, m);
    p.lobe = kPhongMirrorLobe;
    // The usual Beckmann/Phong correspondence n = 2/alpha^2 - 2 with glTF's alpha =
    // roughness^2. Below roughness ~0.12 it exceeds the cap; at 0 it would divide by zero.
    const float alpha = r * r;
    const float alpha2 = alpha * alpha;
    const float n = alpha2 > 2.0f / (kMaxLafortuneExponent + 2.0f) ? 2.0f / alpha2 - 2.0f : kMaxLafortuneExponent;
    p.exponent = std::clamp(n, kMinLafortuneExponent, kMaxLafortuneExponent);
    p.fresnelPhi = kMetallicRoughnessFresnelPhi;
    p.tangentRotation = 0.0f;
    return p;
}

std::optional<LafortuneParams> materialPreset(std::string_view name)
{
    const Preset* preset = findPreset(name);
    if (!preset) {
        return std::nullopt;
    }
    return preset->params;
}

glm::vec3 materialPresetEmission(std::string_view name)
{
    return name == "emissive" ? glm::vec3(kEmissivePresetRadiance) : glm::vec3(0.0f);
}

GltfTransmission materialPresetTransmission(std::string_view name)
{
    GltfTransmission t;
    if (name == "glass" || name == "thin_glass") {
        t.factor = 1.0f;
        t.ior = 1.5f; // F0 0.04, the preset's rho_s
        // Any thickness above 0 makes it solid (the view bends at the surface); with no
        // attenuation its value changes nothing else. 0 is glTF's thin-walled surface.
        t.thickness = name == "glass" ? 1.0f : 0.0f;
    }
    return t;
}

std::span<const std::string_view> materialPresetNames()
{
    return kPresetNames;
}

bool materialPresetUsesSwirlRotation(std::string_view name)
{
    const Preset* preset = findPreset(name);
    return preset && preset->swirl;
}

Image8 makeSwirlRotationTexture(int size)
{
    if (size < 1 || size > kMaxTextureSide) {
        throw InputError("swirl texture size " + std::to_string(size) + " is outside [1, " +
                         std::to_string(kMaxTextureSide) + "]");
    }
    Image8 image(size, size, 4);
    const double c = size / 2.0;
    for (int row = 0; row < size; ++row) {
        const double y = c - (row + 0.5); // up the image: along B
        for (int col = 0; col < size; ++col) {
            const double x = col + 0.5 - c;
            // The tangent is perpendicular to the radius; the lobe is symmetric under T -> -T,
            // so the angle is only needed modulo pi.
            double angle = std::fmod(std::atan2(y, x) + std::numbers::pi / 2.0, std::numbers::pi);
            if (angle < 0.0) {
                angle += std::numbers::pi;
            }
            const auto value = uint8_t(std::lround(angle / std::numbers::pi * 255.0));
            uint8_t* texel = image.at(col, row);
            texel[0] = texel[1] = texel[2] = value;
            texel[3] = 255;
        }
    }
    return image;
}

} // namespace lumar
