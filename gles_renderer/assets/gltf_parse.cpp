#include "gles_renderer/assets/gltf_parse.h"

#include <algorithm>
#include <cctype>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <limits>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <stb_image.h>
#include <webp/decode.h>

#include "core/error.h"
#include "core/file_bytes.h"
#include "core/log.h"
#include "gles_renderer/assets/gltf_compression.h"
#include "gles_renderer/assets/gltf_json_check.h"
#include "gles_renderer/assets/gltf_parse_messages.h"

namespace lumar::gltf {
namespace {

// A .glb's length field is 32 bits and tinygltf takes an unsigned int; models we render are
// tens of megabytes, so anything near the limit is refused before it is read.
constexpr uint64_t kMaxFileBytes = uint64_t(1) << 30;
// Larger textures than any GPU we target can sample; refused before stb allocates them.
constexpr int kMaxImageSide = 16384;

constexpr uint32_t kGlbMagic = 0x46546C67;  // "glTF"
constexpr uint32_t kChunkJson = 0x4E4F534A; // "JSON"

// The GLB container (glTF 2.0 §4.4): a 12-byte header, then chunks of (length, type, data),
// the first one JSON. tinygltf 2.7 reads a BIN chunk's 8-byte header without counting it
// against the file length, so every chunk is checked here first.
void checkGlbContainer(const std::vector<unsigned char>& bytes)
{
    if (bytes.size() < 12 || readLittleEndian32(bytes.data()) != kGlbMagic) {
        throw InputError("not a binary glTF file (no glTF magic)");
    }
    const uint32_t version = readLittleEndian32(bytes.data() + 4);
    if (version != 2) {
        throw InputError("GLB version " + std::to_string(version) + " is not supported (only 2)");
    }
    const uint64_t length = readLittleEndian32(bytes.data() + 8);
    if (length > bytes.size()) {
        throw InputError("truncated GLB: the header declares " + std::to_string(length) + " bytes, the file has " +
                         std::to_string(bytes.size()));
    }
    uint64_t offset = 12;
    for (int chunk = 0; offset < length; ++chunk) {
        if (length - offset < 8) {
            throw InputError("GLB chunk " + std::to_string(chunk) + " header runs past the end of the data");
        }
        const uint64_t chunkLength = readLittleEndian32(bytes.data() + offset);
        const uint32_t chunkType = readLittleEndian32(bytes.data() + offset + 4);
        if (chunk == 0 && chunkType != kChunkJson) {
            throw InputError("the first GLB chunk is not JSON");
        }
        if (chunkLength > length - offset - 8) {
            throw InputError("GLB chunk " + std::to_string(chunk) + " (" + std::to_string(chunkLength) +
                             " bytes) runs past the end of the data");
        }
        offset += 8 + chunkLength;
    }
    if (offset == 12) {
        throw InputError("the GLB holds no JSON chunk");
    }
}

bool hasGlbExtension(const std::filesystem::path& file)
{
    std::string extension = file.extension().string();
    std::transform(extension.begin(), extension.end(), extension.begin(),
                   [](unsigned char c) { return char(std::tolower(c)); });
    return extension == ".glb";
}

// What the image callback needs: the model being filled (tinygltf parses buffers and buffer
// views before images).
struct ImageLoaderContext {
    const tinygltf::Model* model = nullptr;
    std::string error; // the first image problem, in our words (tinygltf's report is not)
};

bool failImage(ImageLoaderContext* context, std::string* err, const std::string& message)
{
    if (context->error.empty()) {
        context->error = message;
    }
    *err += message + "\n";
    return false;
}

bool startsWith(const unsigned char* bytes, int size, std::string_view magic, int offset = 0)
{
    return size >= offset + int(magic.size()) && std::memcmp(bytes + offset, magic.data(), magic.size()) == 0;
}

// EXT_texture_webp's images (libwebp; stb_image has no WebP decoder) as 8-bit RGBA.
bool decodeWebp(tinygltf::Image* image, const std::string& what, const unsigned char* bytes, int size,
                ImageLoaderContext* context, std::string* err)
{
    int width = 0, height = 0;
    if (!WebPGetInfo(bytes, size_t(size), &width, &height)) {
        return failImage(context, err, what + " is not a valid WebP image");
    }
    if (width > kMaxImageSide || height > kMaxImageSide) {
        return failImage(context, err,
                         what + ": " + std::to_string(width) + "x" + std::to_string(height) + " is larger than " +
                             std::to_string(kMaxImageSide) + " pixels a side");
    }
    image->image.resize(size_t(width) * size_t(height) * 4);
    if (WebPDecodeRGBAInto(bytes, size_t(size), image->image.data(), image->image.size(), width * 4) == nullptr) {
        image->image.clear();
        return failImage(context, err, what + ": the WebP data cannot be decoded");
    }
    image->width = width;
    image->height = height;
    image->component = 4;
    image->bits = 8;
    image->pixel_type = TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE;
    return true;
}

// tinygltf 2.7 passes &buffer.data[view.byteOffset] and view.byteLength without checking
// that the view fits in the buffer; check that, and the image size, before decoding.
bool loadImageChecked(tinygltf::Image* image, const int imageIndex, std::string* err, std::string* warn,
                      int requiredWidth, int requiredHeight, const unsigned char* bytes, int size, void* userData)
{
    auto* context = static_cast<ImageLoaderContext*>(userData);
    const std::string what = "image " + std::to_string(imageIndex);
    if (image->bufferView >= 0) {
        const tinygltf::Model& model = *context->model;
        if (size_t(image->bufferView) >= model.bufferViews.size()) {
            return failImage(context, err,
                             what + ": bufferView " + std::to_string(image->bufferView) + " does not exist");
        }
        const tinygltf::BufferView& view = model.bufferViews[size_t(image->bufferView)];
        if (view.buffer < 0 || size_t(view.buffer) >= model.buffers.size() ||
            view.byteOffset > model.buffers[size_t(view.buffer)].data.size() ||
            view.byteLength > model.buffers[size_t(view.buffer)].data.size() - view.byteOffset ||
            view.byteLength > size_t(std::numeric_limits<int>::max())) {
            return failImage(context, err,
                             what + ": bufferView " + std::to_string(image->bufferView) + " lies outside its buffer");
        }
    }
    if (bytes == nullptr || size <= 0) {
        return failImage(context, err, what + ": no image data");
    }
    if (startsWith(bytes, size, "RIFF") && startsWith(bytes, size, "WEBP", 8)) {
        return decodeWebp(image, what, bytes, size, context, err);
    }
    int width = 0, height = 0, components = 0;
    if (!stbi_info_from_memory(bytes, size, &width, &height, &components)) {
        if (startsWith(bytes, size, "\xABKTX 20")) {
            return failImage(context, err, what + " is a KTX2 image (KHR_texture_basisu), which lumar does not decode");
        }
        return failImage(context, err, what + " is not an image lumar can decode (PNG, JPEG or WebP)");
    }
    if (width > kMaxImageSide || height > kMaxImageSide) {
        return failImage(context, err,
                         what + ": " + std::to_string(width) + "x" + std::to_string(height) + " is larger than " +
                             std::to_string(kMaxImageSide) + " pixels a side");
    }
    // tinygltf's own decoder (stb_image); its options struct is not in the public header, and
    // without one it expands every image to 4 components (8 or 16 bits), which suits us.
    return tinygltf::LoadImageData(image, imageIndex, err, warn, requiredWidth, requiredHeight, bytes, size, nullptr);
}

void logLines(const std::filesystem::path& file, std::string_view text)
{
    while (!text.empty()) {
        const size_t end = text.find('\n');
        const std::string_view line = text.substr(0, end);
        if (line.find_first_not_of(" \t\r") != std::string_view::npos) {
            LUMAR_LOG(Render, Warn) << file.string() << ": " << line;
        }
        text.remove_prefix(end == std::string_view::npos ? text.size() : end + 1);
    }
}

// The JSON text: the whole file, or a checked GLB's first chunk.
std::string_view jsonText(const std::vector<unsigned char>& bytes, bool binary)
{
    const auto* text = reinterpret_cast<const char*>(bytes.data());
    if (!binary) {
        return {text, bytes.size()};
    }
    return {text + 20, readLittleEndian32(bytes.data() + 12)};
}

// tinygltf reads external buffers and images through these callbacks. The uris were checked
// already (gltf_json_check.h); this second check resolves symbolic links too, so a link in the
// model's folder cannot lead outside it either, and applies the loader's size bound. tinygltf
// also tries each uri relative to the working directory: that path fails the check.
struct ModelFolder {
    std::filesystem::path root; // canonical
};

bool insideFolder(const std::string& path, const ModelFolder& folder)
{
    std::error_code ec;
    const std::filesystem::path resolved = std::filesystem::weakly_canonical(path, ec);
    if (ec) {
        return false;
    }
    const auto [rootEnd, unused] =
        std::mismatch(folder.root.begin(), folder.root.end(), resolved.begin(), resolved.end());
    return rootEnd == folder.root.end();
}

bool fileInsideFolder(const std::string& path, void* userData)
{
    std::error_code ec;
    return insideFolder(path, *static_cast<const ModelFolder*>(userData)) && std::filesystem::is_regular_file(path, ec);
}

std::string pathAsIs(const std::string& path, void*)
{
    return path; // no expansion of '~' or variables: a uri is a path inside the folder
}

bool readFileInsideFolder(std::vector<unsigned char>* out, std::string* err, const std::string& path, void* userData)
{
    if (!insideFolder(path, *static_cast<const ModelFolder*>(userData))) {
        *err += "outside the model's folder";
        return false;
    }
    try {
        *out = readFileBytes(path, kMaxFileBytes);
    } catch (const InputError& e) {
        *err += e.what();
        return false;
    }
    return true;
}

bool refuseWrite(std::string* err, const std::string&, const std::vector<unsigned char>&, void*)
{
    *err += "lumar does not write glTF files";
    return false;
}

} // namespace

tinygltf::Model parseGltfFile(const std::filesystem::path& file)
{
    const std::vector<unsigned char> bytes = readFileBytes(file, kMaxFileBytes);
    if (bytes.empty())
        throw InputError("the file is empty");
    const bool binary = hasGlbExtension(file) || (bytes.size() >= 4 && readLittleEndian32(bytes.data()) == kGlbMagic);
    if (binary) {
        checkGlbContainer(bytes);
    }
    checkGltfJson(jsonText(bytes, binary));
    // Draco and meshopt files: the JSON parts tinygltf cannot read moved aside (gltf_compression.h).
    std::vector<unsigned char> prepared;
    if (const std::optional<std::string> json = prepareCompressedJson(jsonText(bytes, binary), binary)) {
        prepared = binary ? glbWithJson(bytes, *json) : std::vector<unsigned char>(json->begin(), json->end());
    }
    const std::vector<unsigned char>& input = prepared.empty() ? bytes : prepared;
    std::error_code ec;
    ModelFolder folder{std::filesystem::weakly_canonical(
        file.has_parent_path() ? file.parent_path() : std::filesystem::path("."), ec)};
    if (ec) {
        throw InputError("cannot resolve the model's folder: " + ec.message());
    }

    tinygltf::Model model;
    ImageLoaderContext imageContext;
    imageContext.model = &model;

    tinygltf::TinyGLTF loader;
    loader.SetImageLoader(&loadImageChecked, &imageContext);
    loader.SetFsCallbacks({&fileInsideFolder, &pathAsIs, &readFileInsideFolder, &refuseWrite, &folder});
    std::string err, warn;
    const std::string baseDir = file.parent_path().string();
    bool ok = false;
    try {
        ok = binary ? loader.LoadBinaryFromMemory(&model, &err, &warn, input.data(), unsigned(input.size()), baseDir)
                    : loader.LoadASCIIFromString(&model, &err, &warn, reinterpret_cast<const char*>(input.data()),
                                                 unsigned(input.size()), baseDir);
    } catch (const std::exception& e) {
        // tinygltf only guards its JSON parse; anything else it throws is still about the file.
        throw InputError(parseFailureInOurWords(e.what(), jsonText(bytes, binary), binary));
    }
    logLines(file, warn);
    if (!ok) {
        // Our own image checks speak first; tinygltf's wording never reaches the user.
        throw InputError(!imageContext.error.empty() ? imageContext.error
                                                     : parseFailureInOurWords(err, jsonText(bytes, binary), binary));
    }
    logLines(file, err); // tinygltf reports some recoverable problems as errors and goes on
    decodeCompressedData(model);
    return model;
}

} // namespace lumar::gltf
