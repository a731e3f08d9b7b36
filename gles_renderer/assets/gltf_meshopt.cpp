#include "gles_renderer/assets/gltf_meshopt.h"

#include <string>
#include <vector>

#include "core/error.h"
#include "gles_renderer/assets/gltf_compression.h"

#if LUMAR_HAVE_MESHOPT_DECODER
#include <meshoptimizer.h>
#endif

namespace lumar::gltf {

#if LUMAR_HAVE_MESHOPT_DECODER

namespace {

// meshoptimizer's codecs cannot expand data by more than this: the attribute codec spends at
// least 2 header bits on each group of 16 bytes (a group of zero deltas costs nothing else),
// the triangle codec a byte per triangle of up to 12 bytes, the index codec a byte per index
// (EXT_meshopt_compression, appendix A). A larger count is a lie that would only allocate.
constexpr size_t kMaxExpansion = 64;

struct CompressedView {
    size_t buffer = 0;
    size_t byteOffset = 0;
    size_t byteLength = 0;
    size_t byteStride = 0;
    size_t count = 0;
    std::string mode;
    std::string filter = "NONE";
};

size_t requiredCount(const tinygltf::Value& extension, const char* key, const std::string& what)
{
    const std::optional<size_t> value = countMember(extension, key, what);
    if (!value) {
        throw InputError(what + ": " + key + " is missing");
    }
    return *value;
}

std::string stringMember(const tinygltf::Value& extension, const char* key, const std::string& what,
                         const std::string& fallback)
{
    if (!extension.Has(key)) {
        return fallback;
    }
    const tinygltf::Value& value = extension.Get(key);
    if (!value.IsString()) {
        throw InputError(what + ": " + key + " is not a string");
    }
    return value.Get<std::string>();
}

// The extension object read and checked against the specification's rules.
CompressedView readExtension(const tinygltf::Model& model, const tinygltf::BufferView& view,
                             const tinygltf::Value& extension, const std::string& what)
{
    if (!extension.IsObject()) {
        throw InputError(what + ": the extension is not an object with buffer, byteLength, byteStride, count and mode");
    }
    CompressedView c;
    c.buffer = requiredCount(extension, "buffer", what);
    c.byteOffset = countMember(extension, "byteOffset", what).value_or(0);
    c.byteLength = requiredCount(extension, "byteLength", what);
    c.byteStride = requiredCount(extension, "byteStride", what);
    c.count = requiredCount(extension, "count", what);
    if (!extension.Has("mode")) {
        throw InputError(what + ": mode is missing");
    }
    c.mode = stringMember(extension, "mode", what, "");
    c.filter = stringMember(extension, "filter", what, "NONE");

    const bool attributes = c.mode == "ATTRIBUTES";
    if (!attributes && c.mode != "TRIANGLES" && c.mode != "INDICES") {
        throw InputError(what + ": mode '" + c.mode.substr(0, 40) + "' is not ATTRIBUTES, TRIANGLES or INDICES");
    }
    if (c.filter != "NONE" && c.filter != "OCTAHEDRAL" && c.filter != "QUATERNION" && c.filter != "EXPONENTIAL") {
        throw InputError(what + ": filter '" + c.filter.substr(0, 40) +
                         "' is not NONE, OCTAHEDRAL, QUATERNION or EXPONENTIAL");
    }
    const std::string stride = "byteStride " + std::to_string(c.byteStride);
    if (attributes && (c.byteStride == 0 || c.byteStride % 4 != 0 || c.byteStride > 256)) {
        throw InputError(what + ": " + stride + " is not a multiple of 4 up to 256 (ATTRIBUTES)");
    }
    if (!attributes && c.byteStride != 2 && c.byteStride != 4) {
        throw InputError(what + ": " + stride + " is not 2 or 4 (" + c.mode + ")");
    }
    if (!attributes && c.filter != "NONE") {
        throw InputError(what + ": filter " + c.filter + " is only allowed with ATTRIBUTES");
    }
    if ((c.filter == "OCTAHEDRAL" && c.byteStride != 4 && c.byteStride != 8) ||
        (c.filter == "QUATERNION" && c.byteStride != 8)) {
        throw InputError(what + ": " + stride + " does not suit filter " + c.filter);
    }
    if (c.mode == "TRIANGLES" && c.count % 3 != 0) {
        throw InputError(what + ": count " + std::to_string(c.count) + " is not a multiple of 3 (TRIANGLES)");
    }
    if (view.byteStride != 0 && view.byteStride != c.byteStride) {
        throw InputError(what + ": the bufferView's byteStride " + std::to_string(view.byteStride) +
                         " differs from the extension's " + std::to_string(c.byteStride));
    }
    // byteStride <= 256, so the product fits whenever count does below.
    if (c.count > (size_t(1) << 32) || c.count * c.byteStride != view.byteLength) {
        throw InputError(what + ": count " + std::to_string(c.count) + " x " + stride + " is not the bufferView's " +
                         "byteLength " + std::to_string(view.byteLength));
    }
    if (c.buffer >= model.buffers.size()) {
        throw InputError(what + ": buffer " + std::to_string(c.buffer) + " does not exist");
    }
    const size_t bufferBytes = model.buffers[c.buffer].data.size();
    if (c.byteOffset > bufferBytes || c.byteLength > bufferBytes - c.byteOffset) {
        throw InputError(what + ": the compressed data (offset " + std::to_string(c.byteOffset) + ", length " +
                         std::to_string(c.byteLength) + ") lies outside buffer " + std::to_string(c.buffer) + " of " +
                         std::to_string(bufferBytes) + " bytes");
    }
    return c;
}

std::vector<unsigned char> decode(const tinygltf::Model& model, const CompressedView& c, const std::string& what)
{
    std::vector<unsigned char> out(c.count * c.byteStride);
    if (c.count == 0) {
        return out;
    }
    const unsigned char* source = model.buffers[c.buffer].data.data() + c.byteOffset;
    int result = 0;
    if (c.mode == "ATTRIBUTES") {
        result = meshopt_decodeVertexBuffer(out.data(), c.count, c.byteStride, source, c.byteLength);
    } else if (c.mode == "TRIANGLES") {
        result = meshopt_decodeIndexBuffer(out.data(), c.count, c.byteStride, source, c.byteLength);
    } else {
        result = meshopt_decodeIndexSequence(out.data(), c.count, c.byteStride, source, c.byteLength);
    }
    if (result != 0) {
        throw InputError(what + ": the compressed " + c.mode + " data (" + std::to_string(c.byteLength) +
                         " bytes) is truncated or corrupt");
    }
    // The filters turn every stored bit pattern into some number (the exponential one into
    // any float, non-finite included: the accessor readers refuse those).
    if (c.filter == "OCTAHEDRAL") {
        meshopt_decodeFilterOct(out.data(), c.count, c.byteStride);
    } else if (c.filter == "QUATERNION") {
        meshopt_decodeFilterQuat(out.data(), c.count, c.byteStride);
    } else if (c.filter == "EXPONENTIAL") {
        meshopt_decodeFilterExp(out.data(), c.count, c.byteStride);
    }
    return out;
}

} // namespace

bool meshoptDecoderBuilt()
{
    return true;
}

void decodeMeshoptBufferViews(tinygltf::Model& model, size_t& bytesLeft)
{
    for (size_t v = 0; v < model.bufferViews.size(); ++v) {
        const auto found = model.bufferViews[v].extensions.find(kMeshopt);
        if (found == model.bufferViews[v].extensions.end()) {
            continue;
        }
        const std::string what = "bufferView " + std::to_string(v) + " (" + kMeshopt + ")";
        const CompressedView c = readExtension(model, model.bufferViews[v], found->second, what);
        const size_t decodedBytes = c.count * c.byteStride;
        if (decodedBytes > c.byteLength * kMaxExpansion + 64) {
            throw InputError(what + ": " + std::to_string(c.byteLength) + " compressed bytes cannot hold " +
                             std::to_string(decodedBytes) + " bytes of data");
        }
        if (decodedBytes > bytesLeft) {
            throw InputError(what + ": the decoded data would exceed " + std::to_string(kMaxDecodedBytes) +
                             " bytes in all");
        }
        bytesLeft -= decodedBytes;

        tinygltf::Buffer decoded;
        decoded.data = decode(model, c, what);
        model.buffers.push_back(std::move(decoded));
        tinygltf::BufferView& view = model.bufferViews[v];
        view.buffer = int(model.buffers.size() - 1);
        view.byteOffset = 0;
        view.byteLength = decodedBytes;
        view.extensions.erase(kMeshopt);
    }
}

#else // built without the decoder: files that only use the extension read the fallback data

bool meshoptDecoderBuilt()
{
    return false;
}

void decodeMeshoptBufferViews(tinygltf::Model&, size_t&) {}

#endif

} // namespace lumar::gltf
