#include "config/material_sidecar.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iterator>
#include <limits>
#include <map>
#include <memory>
#include <string_view>
#include <vector>

#include <stb_image.h>
#include <toml++/toml.h>

#include "config/toml_parse.h"
#include "config/toml_text.h"
#include "core/error.h"
#include "core/file_bytes.h"
#include "core/log.h"
#include "gles_renderer/assets/lafortune_material.h"

namespace lumar {
namespace {

using toml_text::formatNumber;
using toml_text::typeName;

// A sidecar is a few hundred bytes; anything this large is not one.
constexpr uintmax_t kMaxSidecarBytes = uintmax_t(1) << 20;
constexpr uintmax_t kMaxTextureFileBytes = uintmax_t(256) << 20;
constexpr int kMaxTextureSide = 16384;

std::string quoteName(std::string_view name)
{
    return "\"" + std::string(name) + "\"";
}

// Any image stb decodes (PNG in practice), as RGBA8; a grey image becomes (g, g, g, 255).
Image8 decodeImage(const std::filesystem::path& file)
{
    const std::vector<uint8_t> bytes = readFileBytes(file, kMaxTextureFileBytes);
    if (bytes.empty() || bytes.size() > size_t(std::numeric_limits<int>::max())) {
        throw InputError("not an image");
    }
    int width = 0, height = 0, components = 0;
    if (!stbi_info_from_memory(bytes.data(), int(bytes.size()), &width, &height, &components)) {
        const char* reason = stbi_failure_reason();
        throw InputError(std::string("cannot decode: ") + (reason ? reason : "unknown image format"));
    }
    if (width > kMaxTextureSide || height > kMaxTextureSide) {
        throw InputError(std::to_string(width) + "x" + std::to_string(height) + " is larger than " +
                         std::to_string(kMaxTextureSide) + " pixels a side");
    }
    const std::unique_ptr<stbi_uc, decltype(&stbi_image_free)> pixels(
        stbi_load_from_memory(bytes.data(), int(bytes.size()), &width, &height, &components, 4), &stbi_image_free);
    if (!pixels) {
        const char* reason = stbi_failure_reason();
        throw InputError(std::string("cannot decode: ") + (reason ? reason : "unknown stb_image error"));
    }
    Image8 image(width, height, 4);
    std::copy(pixels.get(), pixels.get() + image.data.size(), image.data.begin());
    return image;
}

// Validating reader of one [material."NAME"] table; messages are "FILE:LINE: KEY: what".
class EntryReader {
public:
    EntryReader(const toml::table& table, std::string keyPath, const std::string& fileName)
        : table_(table), keyPath_(std::move(keyPath)), fileName_(fileName)
    {
    }

    [[noreturn]] void fail(const toml::node* node, std::string_view key, const std::string& what) const
    {
        const toml::source_region& where = node ? node->source() : table_.source();
        const auto line = where.begin.line ? where.begin.line : table_.source().begin.line;
        throw InputError(fileName_ + ":" + std::to_string(line ? line : 1) + ": " + keyPath_ + "." + std::string(key) +
                         ": " + what);
    }

    void rejectUnknownKeys(std::initializer_list<std::string_view> known) const
    {
        for (const auto& [key, node] : table_) {
            if (std::find(known.begin(), known.end(), key.str()) == known.end()) {
                std::string list;
                for (const std::string_view k : known) {
                    list += (list.empty() ? "" : ", ") + std::string(k);
                }
                fail(&node, key.str(), "unknown key (known: " + list + ")");
            }
        }
    }

    std::optional<std::string> string(std::string_view key) const
    {
        const toml::node* node = table_.get(key);
        if (!node) {
            return std::nullopt;
        }
        const auto* value = node->as_string();
        if (!value) {
            fail(node, key, std::string("expected a string, found ") + typeName(*node));
        }
        return value->get();
    }

    std::optional<float> number(std::string_view key, double min, double max, bool maxExclusive) const
    {
        const toml::node* node = table_.get(key);
        if (!node) {
            return std::nullopt;
        }
        double value = 0.0;
        if (const auto* f = node->as_floating_point()) {
            value = f->get();
        } else if (const auto* i = node->as_integer()) {
            value = double(i->get());
        } else {
            fail(node, key, std::string("expected a number, found ") + typeName(*node));
        }
        const bool above = maxExclusive ? value >= max : value > max;
        if (!std::isfinite(value) || value < min || above) {
            fail(node, key,
                 formatNumber(value) + " is outside [" + formatNumber(min) + ", " + formatNumber(max) +
                     (maxExclusive ? ")" : "]"));
        }
        return float(value);
    }

    std::optional<glm::vec3> vec3(std::string_view key, double min, double max) const
    {
        const toml::node* node = table_.get(key);
        if (!node) {
            return std::nullopt;
        }
        const std::string expected =
            "expected an array of 3 numbers within [" + formatNumber(min) + ", " + formatNumber(max) + "]";
        const auto* array = node->as_array();
        if (!array || array->size() != 3) {
            fail(node, key, expected);
        }
        glm::vec3 out;
        for (int i = 0; i < 3; ++i) {
            const auto v = (*array)[size_t(i)].value<double>();
            if (!v || !std::isfinite(*v) || *v < min || *v > max) {
                fail(node, key, expected);
            }
            out[i] = float(*v);
        }
        return out;
    }

private:
    const toml::table& table_;
    std::string keyPath_;
    const std::string& fileName_;
};

MaterialOverride readEntry(const toml::table& table, const std::string& keyPath, const std::string& fileName,
                           const std::filesystem::path& baseDir)
{
    EntryReader r(table, keyPath, fileName);
    r.rejectUnknownKeys({"preset", "diffuse", "specular", "lobe", "exponent", "fresnel_phi", "tangent_rotation",
                         "tangent_rotation_texture"});

    MaterialOverride entry;
    entry.line = int(table.source().begin.line);
    entry.preset = r.string("preset");
    if (entry.preset && !materialPreset(*entry.preset)) {
        std::string list;
        for (const std::string_view name : materialPresetNames()) {
            list += (list.empty() ? "" : ", ") + std::string(name);
        }
        r.fail(table.get("preset"), "preset", quoteName(*entry.preset) + " is not one of " + list);
    }
    entry.diffuse = r.vec3("diffuse", 0.0, 1.0);
    entry.specular = r.vec3("specular", 0.0, 1.0);
    entry.lobe = r.vec3("lobe", -kMaxLobeCoefficient, kMaxLobeCoefficient);
    if (entry.lobe && *entry.lobe == glm::vec3(0.0f)) {
        r.fail(table.get("lobe"), "lobe", "all three coefficients are 0: the lobe has no direction");
    }
    entry.exponent = r.number("exponent", kMinLafortuneExponent, kMaxLafortuneExponent, false);
    entry.fresnelPhi = r.number("fresnel_phi", 0.0, 1.0, true);
    entry.tangentRotation = r.number("tangent_rotation", 0.0, 1.0, false);

    if (const std::optional<std::string> texture = r.string("tangent_rotation_texture")) {
        const toml::node* node = table.get("tangent_rotation_texture");
        if (*texture == "swirl") {
            entry.rotationTexture = MaterialOverride::RotationTexture::Swirl;
        } else if (*texture == "none") {
            entry.rotationTexture = MaterialOverride::RotationTexture::None;
        } else if (texture->empty()) {
            r.fail(node, "tangent_rotation_texture", "must be \"swirl\", \"none\" or an image path");
        } else {
            std::filesystem::path path(*texture);
            if (path.is_relative()) {
                path = baseDir / path;
            }
            path = path.lexically_normal();
            try {
                entry.rotationImage = decodeImage(path);
            } catch (const InputError& e) {
                r.fail(node, "tangent_rotation_texture", path.string() + ": " + e.what());
            }
            entry.rotationTexture = MaterialOverride::RotationTexture::Image;
        }
    }
    return entry;
}

} // namespace

MaterialOverrides loadMaterialSidecar(const std::filesystem::path& file)
{
    const std::string fileName = file.string();
    std::vector<uint8_t> bytes;
    try {
        bytes = readFileBytes(file, kMaxSidecarBytes);
    } catch (const InputError& e) {
        throw InputError(fileName + ": " + e.what());
    }
    const toml::table root =
        parseToml(std::string_view(reinterpret_cast<const char*>(bytes.data()), bytes.size()), fileName);

    MaterialOverrides sidecar;
    sidecar.source = fileName;
    const std::filesystem::path baseDir = file.has_parent_path() ? file.parent_path() : std::filesystem::path(".");
    for (const auto& [key, node] : root) {
        if (key.str() != "material") {
            throw InputError(fileName + ":" + std::to_string(node.source().begin.line) + ": " + std::string(key.str()) +
                             ": unknown key (the file holds [material.\"NAME\"] tables only)");
        }
    }
    const toml::node* materials = root.get("material");
    if (!materials) {
        return sidecar; // an empty sidecar changes nothing
    }
    const auto* table = materials->as_table();
    if (!table) {
        throw InputError(fileName + ":" + std::to_string(materials->source().begin.line) +
                         ": material: expected a table of [material.\"NAME\"] tables, found " + typeName(*materials));
    }
    for (const auto& [name, node] : *table) {
        const std::string keyPath = "material." + quoteName(name.str());
        const auto* entry = node.as_table();
        if (!entry) {
            const auto line = node.source().begin.line;
            throw InputError(fileName + ":" + std::to_string(line ? line : 1) + ": " + keyPath +
                             ": expected a table, found " + typeName(node));
        }
        sidecar.materials.emplace(std::string(name.str()), readEntry(*entry, keyPath, fileName, baseDir));
    }
    LUMAR_LOG(Config, Debug) << fileName << ": " << sidecar.materials.size() << " material entries";
    return sidecar;
}

} // namespace lumar
