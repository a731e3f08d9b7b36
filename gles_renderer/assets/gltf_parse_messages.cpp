#include "gles_renderer/assets/gltf_parse_messages.h"

#include <optional>
#include <regex>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace lumar::gltf {
namespace {

using nlohmann::json;

// The JSON's own problem, where it has one: tinygltf hands on nlohmann's exception text.
std::optional<std::string> jsonProblem(std::string_view text, json& document)
{
    if (text.size() < 2) {
        return "the JSON is too short to be a glTF document";
    }
    try {
        document = json::parse(text.begin(), text.end());
    } catch (const json::parse_error& e) {
        return "the JSON is malformed near byte " + std::to_string(e.byte);
    } catch (const json::out_of_range&) {
        return "the JSON holds a number too large to read";
    } catch (const json::exception&) {
        return "the JSON cannot be read";
    }
    if (!document.is_object()) {
        return "the JSON's top level is not an object";
    }
    return std::nullopt;
}

std::optional<std::string> bufferWithoutUri(const json& document, bool binary)
{
    const auto buffers = document.find("buffers");
    if (buffers == document.end() || !buffers->is_array()) {
        return std::nullopt;
    }
    for (size_t i = 0; i < buffers->size(); ++i) {
        const json& buffer = (*buffers)[i];
        if (!buffer.is_object() || buffer.contains("uri")) {
            continue;
        }
        if (!binary) {
            return "buffer " + std::to_string(i) + " has no uri and the file is not a .glb";
        }
        if (i > 0) {
            return "buffer " + std::to_string(i) + " has no uri (only buffer 0 of a .glb may use its BIN chunk)";
        }
    }
    return std::nullopt;
}

// The index of the buffer whose uri is `uri` (as tinygltf decoded it), or -1.
int bufferWithUri(const json& document, const std::string& uri)
{
    const auto buffers = document.find("buffers");
    if (buffers == document.end() || !buffers->is_array()) {
        return -1;
    }
    for (size_t i = 0; i < buffers->size(); ++i) {
        const json& buffer = (*buffers)[i];
        if (buffer.is_object() && buffer.contains("uri") && buffer["uri"].is_string()) {
            const std::string own = buffer["uri"].get<std::string>();
            if (own == uri ||
                (uri.size() >= own.size() && uri.compare(uri.size() - own.size(), own.size(), own) == 0)) {
                return int(i);
            }
        }
    }
    return -1;
}

// The compression extensions a file lists, for messages about accessors without data.
std::string compressionNote(const json& document)
{
    const auto used = document.find("extensionsUsed");
    if (used == document.end() || !used->is_array()) {
        return {};
    }
    for (const json& name : *used) {
        if (name == "KHR_draco_mesh_compression" || name == "EXT_meshopt_compression") {
            return " (the file is compressed with " + name.get<std::string>() + ", which lumar does not decode)";
        }
    }
    return {};
}

std::string lowerFirst(std::string text)
{
    if (!text.empty() && text[0] >= 'A' && text[0] <= 'Z') {
        text[0] = char(text[0] - 'A' + 'a');
    }
    return text;
}

// tinygltf's object names ("BufferView", "accessor[3]") as our words ("bufferView", "accessor 3").
std::string objectName(const std::string& text)
{
    static const std::regex indexed(R"((\w+)\[(\d+)\])");
    std::smatch m;
    if (std::regex_search(text, m, indexed)) {
        return m[1].str() + " " + m[2].str();
    }
    return lowerFirst(text);
}

std::string withArticle(const std::string& noun)
{
    const bool vowel = !noun.empty() && std::string_view("aeiou").find(noun[0]) != std::string_view::npos;
    return (vowel ? "an " : "a ") + noun;
}

// One tinygltf report line in our words, or nothing when the line is not recognised.
std::optional<std::string> knownReport(const std::string& line, const json& document)
{
    std::smatch m;
    const auto match = [&](const char* pattern) { return std::regex_search(line, m, std::regex(pattern)); };
    if (match(R"re(accessor\[(\d+)\] invalid bufferView)re")) {
        return "accessor " + m[1].str() + ", a primitive's indices, has no bufferView or one that does not exist" +
               compressionNote(document);
    }
    if (match(R"re(primitive indices accessor out of bounds)re")) {
        return "a mesh primitive's indices accessor does not exist";
    }
    if (match(R"re(^File not found : (.*)$)re") || match(R"re(^File read error : (.*?) : (.*)$)re") ||
        match(R"re(^File is empty : (.*)$)re") || match(R"re(^File size mismatch : (.*?), requestedBytes)re")) {
        const std::string path = m[1].str();
        const int buffer = bufferWithUri(document, path);
        const std::string what = buffer >= 0 ? "buffer " + std::to_string(buffer) + "'s file " : "the file ";
        if (line.rfind("File not found", 0) == 0) {
            return what + "'" + path + "' does not exist";
        }
        if (line.rfind("File is empty", 0) == 0) {
            return what + "'" + path + "' is empty";
        }
        if (line.rfind("File size mismatch", 0) == 0) {
            return what + "'" + path + "' is not the byteLength the buffer declares";
        }
        return what + "'" + path + "' cannot be read: " + m[2].str();
    }
    if (match(R"re(Failed to decode 'uri'.* in Buffer)re")) {
        return "a buffer's data: uri cannot be decoded (or holds fewer bytes than its byteLength)";
    }
    if (match(R"re(Failed to (?:decode|parse) [`']uri[`'] for image\[(\d+)\])re")) {
        return "image " + m[1].str() + "'s uri cannot be decoded";
    }
    if (match(R"re(Neither required `bufferView` nor `uri` defined for image\[(\d+)\])re")) {
        return "image " + m[1].str() + " has neither a uri nor a bufferView";
    }
    if (match(R"re(Only one of `bufferView` or `uri` should be defined.*image\[(\d+)\])re")) {
        return "image " + m[1].str() + " has both a uri and a bufferView";
    }
    if (match(R"re(Failed to parse `bufferView` for image\[(\d+)\])re")) {
        return "image " + m[1].str() + "'s bufferView is not a valid index";
    }
    if (match(R"re(^image\[(\d+)\] bufferView)re")) {
        return "image " + m[1].str() + "'s bufferView does not exist";
    }
    if (match(R"re(^image\[(\d+)\] buffer)re")) {
        return "image " + m[1].str() + "'s bufferView refers to a buffer that does not exist";
    }
    if (match(R"re(STB cannot decode image data for image\[(\d+)\])re") ||
        match(R"re(Invalid image data for image\[(\d+)\])re")) {
        return "image " + m[1].str() + " cannot be decoded (lumar reads PNG, JPEG and WebP)";
    }
    if (match(R"re(Image (?:width|height) mismatch.*image\[(\d+)\])re")) {
        return "image " + m[1].str() + " does not have the size its decoder expected";
    }
    if (match(R"re(Invalid binary data in `Buffer', or GLB with empty BIN chunk)re")) {
        return "buffer 0 has no uri and the .glb has no BIN chunk";
    }
    if (match(R"re(Invalid `byteLength'.*`byteLength' = (\d+), binary size = (\d+))re")) {
        return "buffer 0's byteLength " + m[1].str() + " is larger than the .glb's BIN chunk (" + m[2].str() +
               " bytes)";
    }
    if (match(R"re(Invalid `byteStride' value)re")) {
        return "a bufferView's byteStride is not a multiple of 4 within [4, 252]";
    }
    if (match(R"re(Invalid `componentType` in accessor\. Got (-?\d+))re")) {
        return "an accessor's componentType " + m[1].str() + " is not a glTF component type";
    }
    if (match(R"re(Unsupported `type` for accessor object\. Got "([^"]*)")re")) {
        return "an accessor's type \"" + m[1].str() + "\" is not a glTF accessor type";
    }
    if (match(R"re(the sparse object of this accessor doesn't have (\w+))re")) {
        return "a sparse accessor has no " + m[1].str();
    }
    if (match(R"re(^'([^']+)' property is missing(?:\. )?(?: in `?([^.`']+)`?'?)?)re")) {
        return m[2].matched ? withArticle(objectName(m[2].str())) + " lacks the required field \"" + m[1].str() + "\""
                            : "the required field \"" + m[1].str() + "\" is missing";
    }
    if (match(R"re(^'([^']+)' (?:property|value) is not (an? [\w ]+?)(?: type)?\.)re")) {
        return "the field \"" + m[1].str() + "\" is not " + m[2].str();
    }
    if (match(R"re(^'([^']+)' property is not an array)re")) {
        return "the field \"" + m[1].str() + "\" is not an array";
    }
    if (match(R"re(^`(\w+)' does not contain an JSON object)re")) {
        return "an entry of \"" + m[1].str() + "\" is not a JSON object";
    }
    if (match(R"re(^"(\w+)" object not found)re")) {
        return "\"" + m[1].str() + "\" is missing or not of the right JSON type";
    }
    if (match(R"re(`(\w+)` field is missing in animation[. ](\w+?)s?\b)re")) {
        return "an animation " + m[2].str() + " has no \"" + m[1].str() + "\"";
    }
    if (match(R"re((Orthographic|Perspective) camera description not found)re")) {
        return "a camera has no \"" + lowerFirst(m[1].str()) + "\" object";
    }
    if (match(R"re(Invalid camera type: "([^"]*)")re")) {
        return "a camera's type \"" + m[1].str() + "\" is not perspective or orthographic";
    }
    if (match(R"re(Spot light description not found)re")) {
        return "a spot light has no \"spot\" object";
    }
    if (match(R"re(JSON string too short|Failed to parse JSON object|Root element is not a JSON object)re")) {
        return "the JSON's top level is not an object";
    }
    return std::nullopt;
}

std::vector<std::string> lines(std::string_view text)
{
    std::vector<std::string> out;
    while (!text.empty()) {
        const size_t end = text.find('\n');
        std::string line(text.substr(0, end));
        while (!line.empty() && (line.back() == '\r' || line.back() == ' ')) {
            line.pop_back();
        }
        if (!line.empty()) {
            out.push_back(std::move(line));
        }
        text.remove_prefix(end == std::string_view::npos ? text.size() : end + 1);
    }
    return out;
}

} // namespace

std::string parseFailureInOurWords(std::string_view report, std::string_view json, bool binary)
{
    nlohmann::json document;
    if (const auto problem = jsonProblem(json, document)) {
        return *problem;
    }
    if (const auto problem = bufferWithoutUri(document, binary)) {
        return *problem;
    }
    const std::vector<std::string> reported = lines(report);
    for (const std::string& line : reported) {
        if (const auto known = knownReport(line, document)) {
            return *known;
        }
    }
    // Not recognised: name the object tinygltf pointed at, in our words, without its text.
    static const std::regex indexed(R"((accessor|bufferView|buffer|image|mesh|node|material|texture|sampler|)"
                                    R"(animation|skin|camera|scene)\[(\d+)\])");
    for (const std::string& line : reported) {
        std::smatch m;
        if (std::regex_search(line, m, indexed)) {
            return m[1].str() + " " + m[2].str() + " does not follow the glTF 2.0 specification";
        }
    }
    return "the file does not follow the glTF 2.0 specification";
}

} // namespace lumar::gltf
