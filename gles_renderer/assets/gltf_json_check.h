// Checks on a glTF's JSON made before tinygltf parses it (issue 16):
//  - nesting depth: tinygltf converts `extras` and extension objects to its Value type by
//    recursion, so JSON nested a few thousand levels deep overflows the stack;
//  - what a buffer or image `uri` may reach: a path relative to the model's own folder that
//    stays inside it (no "..", no absolute path, no scheme such as file: or http:), or a data:
//    URI. tinygltf would otherwise read any file the service may read.
// The JSON is streamed through nlohmann's SAX parser (iterative: deep input costs it no stack,
// and no document is built). Internal to lumar_assets: messages carry no file name.
#pragma once

#include <string_view>

namespace lumar::gltf {

// Far deeper than glTF's own structure (about 7 levels) with room for authored extras.
inline constexpr int kMaxJsonDepth = 64;

// Throws InputError for JSON nested deeper than kMaxJsonDepth or a uri that leaves the
// model's folder. Malformed JSON is left to tinygltf, which reports it with its context.
void checkGltfJson(std::string_view json);

// The uri rule above, for one uri (percent-escapes decoded as tinygltf decodes them).
// Returns what is wrong, or an empty string when the uri is allowed.
std::string_view uriProblem(std::string_view uri);

} // namespace lumar::gltf
