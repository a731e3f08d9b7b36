#include "gles_renderer/assets/gltf_compression.h"

#include <algorithm>
#include <limits>

#include <nlohmann/json.hpp>

#include "core/error.h"
#include "gles_renderer/assets/gltf_draco.h"
#include "gles_renderer/assets/gltf_meshopt.h"

namespace lumar::gltf {
namespace {

using Json = nlohmann::json;

// `object[key]` when `object` is an object that has it, else null.
const Json* member(const Json& object, const char* key)
{
    if (!object.is_object()) {
        return nullptr;
    }
    const auto found = object.find(key);
    return found == object.end() ? nullptr : &*found;
}

Json* member(Json& object, const char* key)
{
    return const_cast<Json*>(member(static_cast<const Json&>(object), key));
}

bool listed(const Json& document, const char* list, const char* extension)
{
    const Json* names = member(document, list);
    return names != nullptr && names->is_array() && std::any_of(names->begin(), names->end(), [&](const Json& name) {
               return name.is_string() && name.get_ref<const std::string&>() == extension;
           });
}

// The extension object `name` of `object` (an object), or null.
Json* extensionObject(Json& object, const char* name)
{
    Json* extensions = member(object, "extensions");
    Json* extension = extensions == nullptr ? nullptr : member(*extensions, name);
    return extension != nullptr && extension->is_object() ? extension : nullptr;
}

// Each Draco primitive's "indices" into its extension object: the accessor has no bufferView
// (the Draco data holds the indices), which tinygltf 2.7 refuses for an index accessor.
bool moveDracoIndices(Json& document)
{
    bool changed = false;
    Json* meshes = member(document, "meshes");
    if (meshes == nullptr || !meshes->is_array()) {
        return false;
    }
    for (Json& mesh : *meshes) {
        Json* primitives = member(mesh, "primitives");
        if (primitives == nullptr || !primitives->is_array()) {
            continue;
        }
        for (Json& primitive : *primitives) {
            Json* draco = extensionObject(primitive, kDraco);
            const auto indices = primitive.is_object() ? primitive.find("indices") : primitive.end();
            if (draco == nullptr || indices == primitive.end()) {
                continue;
            }
            (*draco)[kDracoIndicesKey] = *indices;
            primitive.erase(indices);
            changed = true;
        }
    }
    return changed;
}

bool usesMeshopt(const Json& document)
{
    if (listed(document, "extensionsUsed", kMeshopt) || listed(document, "extensionsRequired", kMeshopt)) {
        return true;
    }
    const Json* views = member(document, "bufferViews");
    return views != nullptr && views->is_array() && std::any_of(views->begin(), views->end(), [](const Json& view) {
               const Json* extensions = member(view, "extensions");
               return extensions != nullptr && member(*extensions, kMeshopt) != nullptr;
           });
}

// A meshopt file's fallback buffers (marked so, or placeholders without a uri that are not
// the GLB's binary chunk) hold no data the decoder needs: each becomes a one-byte data: uri,
// so tinygltf neither reads a uri the buffer does not have nor copies a wrong range of the
// binary chunk. The views that point into them are decoded from their compressed source.
bool replaceFallbackBuffers(Json& document, bool binary)
{
    Json* buffers = member(document, "buffers");
    if (buffers == nullptr || !buffers->is_array()) {
        return false;
    }
    bool changed = false;
    for (size_t i = 0; i < buffers->size(); ++i) {
        Json& buffer = (*buffers)[i];
        if (!buffer.is_object()) {
            continue;
        }
        const Json* meshopt = extensionObject(buffer, kMeshopt);
        const Json* fallback = meshopt == nullptr ? nullptr : member(*meshopt, "fallback");
        const bool marked = fallback != nullptr && fallback->is_boolean() && fallback->get<bool>();
        const bool placeholder = !buffer.contains("uri") && (!binary || i > 0);
        if (!marked && !placeholder) {
            continue;
        }
        Json replacement = {{"byteLength", 1}, {"uri", "data:application/octet-stream;base64,AA=="}};
        if (const Json* extensions = member(buffer, "extensions")) {
            replacement["extensions"] = *extensions;
        }
        buffer = std::move(replacement);
        changed = true;
    }
    return changed;
}

std::string missingDecoder(const char* extension, const char* library, const char* option)
{
    return std::string("requires ") + extension + ", but this build of lumar has no decoder for it (" + library +
           ", CMake option " + option + ")";
}

void appendLittleEndian32(std::vector<unsigned char>& out, uint32_t value)
{
    for (int shift = 0; shift < 32; shift += 8) {
        out.push_back(static_cast<unsigned char>(value >> shift));
    }
}

} // namespace

std::optional<size_t> countMember(const tinygltf::Value& object, const char* key, const std::string& what)
{
    if (!object.IsObject() || !object.Has(key)) {
        return std::nullopt;
    }
    const tinygltf::Value& value = object.Get(key);
    if (value.IsInt() && value.Get<int>() >= 0) {
        return size_t(value.Get<int>());
    }
    throw InputError(what + ": " + key + " is not a non-negative integer");
}

std::optional<std::string> prepareCompressedJson(std::string_view json, bool binary)
{
    // Most files use neither extension: they are not parsed a second time.
    if (json.find(kDraco) == std::string_view::npos && json.find(kMeshopt) == std::string_view::npos) {
        return std::nullopt;
    }
    Json document = Json::parse(json.begin(), json.end(), nullptr, false);
    if (document.is_discarded() || !document.is_object()) {
        return std::nullopt; // tinygltf reports what is wrong with the JSON
    }
    if (!dracoDecoderBuilt() && listed(document, "extensionsRequired", kDraco)) {
        throw InputError(missingDecoder(kDraco, "libdraco-dev", "LUMAR_WITH_DRACO"));
    }
    if (!meshoptDecoderBuilt() && listed(document, "extensionsRequired", kMeshopt)) {
        throw InputError(missingDecoder(kMeshopt, "libmeshoptimizer-dev", "LUMAR_WITH_MESHOPT_DECODER"));
    }
    // Without a decoder, a file that only uses an extension is read through its uncompressed
    // fallback data, unchanged.
    bool changed = dracoDecoderBuilt() && moveDracoIndices(document);
    if (meshoptDecoderBuilt() && usesMeshopt(document)) {
        changed = replaceFallbackBuffers(document, binary) || changed;
    }
    if (!changed) {
        return std::nullopt;
    }
    return document.dump(-1, ' ', false, Json::error_handler_t::replace);
}

std::vector<unsigned char> glbWithJson(const std::vector<unsigned char>& glb, std::string_view json)
{
    // checkGlbContainer (gltf_parse.cpp) has checked the header and that the JSON chunk and
    // the declared length lie inside `glb`.
    const size_t oldJsonEnd = 20 + size_t(readLittleEndian32(glb.data() + 12));
    const size_t length = readLittleEndian32(glb.data() + 8);
    const size_t paddedJson = (json.size() + 3) / 4 * 4; // chunks are 4-byte aligned
    const size_t rest = length - oldJsonEnd;
    const size_t total = 20 + paddedJson + rest;
    if (total > std::numeric_limits<uint32_t>::max()) {
        throw InputError("the GLB is too large to rewrite for decompression");
    }
    std::vector<unsigned char> out;
    out.reserve(total);
    out.insert(out.end(), glb.begin(), glb.begin() + 8); // magic and version
    appendLittleEndian32(out, uint32_t(total));
    appendLittleEndian32(out, uint32_t(paddedJson));
    out.insert(out.end(), glb.begin() + 16, glb.begin() + 20); // chunk type "JSON"
    out.insert(out.end(), json.begin(), json.end());
    out.resize(20 + paddedJson, ' ');
    out.insert(out.end(), glb.begin() + std::ptrdiff_t(oldJsonEnd), glb.begin() + std::ptrdiff_t(length));
    return out;
}

void decodeCompressedData(tinygltf::Model& model)
{
    size_t bytesLeft = kMaxDecodedBytes;
    std::vector<std::string> decoded;
    if (meshoptDecoderBuilt()) {
        decodeMeshoptBufferViews(model, bytesLeft);
        decoded.emplace_back(kMeshopt);
    }
    if (dracoDecoderBuilt()) {
        decodeDracoPrimitives(model, bytesLeft);
        decoded.emplace_back(kDraco);
    }
    // The model now holds the decoded data: nothing in it requires the extensions any more
    // (the loader refuses files requiring extensions it does not know).
    for (std::vector<std::string>* names : {&model.extensionsRequired, &model.extensionsUsed}) {
        names->erase(std::remove_if(names->begin(), names->end(),
                                    [&](const std::string& name) {
                                        return std::find(decoded.begin(), decoded.end(), name) != decoded.end();
                                    }),
                     names->end());
    }
}

} // namespace lumar::gltf
