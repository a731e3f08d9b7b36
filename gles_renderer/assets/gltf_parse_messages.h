// tinygltf's failure reports in lumar's words (issue 20): a user sees one line saying what is
// wrong in glTF terms ("buffer 0 has no uri and the file is not a .glb"), never a library's
// internal wording ("'uri' is missing from non binary glTF file buffer.", json.exception...).
// Internal to lumar_assets: the messages carry no file name, the loader adds it.
#pragma once

#include <string>
#include <string_view>

namespace lumar::gltf {

// What is wrong with a glTF whose parse failed: `report` is what tinygltf wrote (or the text
// of what it threw), `json` the document's JSON text (a .gltf, or a .glb's JSON chunk),
// `binary` whether the file is a .glb. The JSON itself is read again where that names the
// problem better (the byte of a syntax error, the buffer without a uri); anything not
// recognised becomes a plain sentence naming the glTF object concerned where one is known.
std::string parseFailureInOurWords(std::string_view report, std::string_view json, bool binary);

} // namespace lumar::gltf
