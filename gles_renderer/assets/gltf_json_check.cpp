#include "gles_renderer/assets/gltf_json_check.h"

#include <cctype>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/error.h"

namespace lumar::gltf {
namespace {

int hexValue(char c)
{
    if (c >= '0' && c <= '9')
        return c - '0';
    if (c >= 'a' && c <= 'f')
        return c - 'a' + 10;
    if (c >= 'A' && c <= 'F')
        return c - 'A' + 10;
    return -1;
}

std::string percentDecoded(std::string_view uri)
{
    std::string out;
    for (size_t i = 0; i < uri.size(); ++i) {
        if (uri[i] == '%' && i + 2 < uri.size() && hexValue(uri[i + 1]) >= 0 && hexValue(uri[i + 2]) >= 0) {
            out.push_back(char(hexValue(uri[i + 1]) * 16 + hexValue(uri[i + 2])));
            i += 2;
        } else {
            out.push_back(uri[i]);
        }
    }
    return out;
}

// A SAX handler that follows the path from the root (which member of which array) to know
// when a string is buffers[i].uri or images[i].uri, and counts depth.
class JsonCheck : public nlohmann::json::json_sax_t {
public:
    bool null() override { return value(); }
    bool boolean(bool) override { return value(); }
    bool number_integer(number_integer_t) override { return value(); }
    bool number_unsigned(number_unsigned_t) override { return value(); }
    bool number_float(number_float_t, const string_t&) override { return value(); }
    bool binary(binary_t&) override { return value(); }
    bool string(string_t& text) override
    {
        // root object > "buffers"/"images" array > element object > "uri"
        if (path_.size() == 3 && path_[0].isObject && (path_[0].key == "buffers" || path_[0].key == "images") &&
            !path_[1].isObject && path_[2].isObject && path_[2].key == "uri") {
            const std::string_view problem = uriProblem(text);
            if (!problem.empty()) {
                error_ = path_[0].key + "[" + std::to_string(path_[1].index) + "].uri '" + text.substr(0, 80) +
                         "': " + std::string(problem);
                return false;
            }
        }
        return value();
    }
    bool start_object(std::size_t) override { return open(true); }
    bool start_array(std::size_t) override { return open(false); }
    bool end_object() override { return close(); }
    bool end_array() override { return close(); }
    bool key(string_t& name) override
    {
        if (!path_.empty())
            path_.back().key = name;
        return true;
    }
    bool parse_error(std::size_t, const std::string&, const nlohmann::json::exception&) override
    {
        return false; // tinygltf parses it again and reports the error with its own words
    }

    [[nodiscard]] const std::string& error() const { return error_; }

private:
    struct Level {
        bool isObject = false;
        std::string key;  // the member being read (objects)
        size_t index = 0; // the element being read (arrays)
    };

    bool value()
    {
        if (!path_.empty() && !path_.back().isObject)
            ++path_.back().index;
        return true;
    }
    bool open(bool isObject)
    {
        if (path_.size() >= size_t(kMaxJsonDepth)) {
            error_ = "the JSON is nested deeper than " + std::to_string(kMaxJsonDepth) + " levels";
            return false;
        }
        path_.push_back({isObject, {}, 0});
        return true;
    }
    bool close()
    {
        if (!path_.empty())
            path_.pop_back();
        return value();
    }

    std::vector<Level> path_;
    std::string error_;
};

} // namespace

std::string_view uriProblem(std::string_view uri)
{
    if (uri.starts_with("data:"))
        return {};
    // A scheme: letters, digits, '+', '-', '.' before the first ':' (RFC 3986 §3.1).
    const size_t colon = uri.find(':');
    if (colon != std::string_view::npos && colon > 0 && std::isalpha(static_cast<unsigned char>(uri[0]))) {
        bool scheme = true;
        for (size_t i = 0; i < colon; ++i) {
            const char c = uri[i];
            scheme = scheme && (std::isalnum(static_cast<unsigned char>(c)) || c == '+' || c == '-' || c == '.');
        }
        if (scheme)
            return "a URI scheme is not allowed (only paths inside the model's folder and data: URIs)";
    }
    const std::string path = percentDecoded(uri);
    if (path.find('\0') != std::string::npos)
        return "holds a NUL byte";
    if (path.starts_with('/') || path.starts_with('\\'))
        return "an absolute path is not allowed (only paths inside the model's folder)";
    size_t start = 0;
    while (start <= path.size()) {
        size_t end = path.find_first_of("/\\", start);
        if (end == std::string::npos)
            end = path.size();
        if (std::string_view(path).substr(start, end - start) == "..")
            return "'..' is not allowed (only paths inside the model's folder)";
        start = end + 1;
    }
    return {};
}

void checkGltfJson(std::string_view json)
{
    JsonCheck check;
    nlohmann::json::sax_parse(json.begin(), json.end(), &check, nlohmann::json::input_format_t::json, false);
    if (!check.error().empty())
        throw InputError(check.error());
}

} // namespace lumar::gltf
