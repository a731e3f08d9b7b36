// The one entry point to toml++ for every TOML file lumar reads (configuration, board
// profiles, material sidecars). toml++ 3.3 trusts its input in two ways that a hostile file
// exploits (issue 16): it recurses once per level of a dotted key or table header, so a key
// nested a few thousand levels deep overflows the stack, and it looks invalid UTF-8 in keys
// up in Unicode tables that end in `unreachable`. A pre-scan refuses both before the parser
// runs: UTF-8 is validated byte by byte, and the nesting depth (table header segments + key
// segments + open arrays and inline tables) and the length of one key are bounded.
#pragma once

#include <cstddef>
#include <string>
#include <string_view>

#include <toml++/toml.h>

namespace lumar {

// Far above what lumar's files use (material."NAME".field is 3 levels, inline arrays add 1)
// and far below where toml++'s recursion needs more than a few kilobytes of stack.
inline constexpr int kMaxTomlDepth = 32;
// One key segment (a bare or quoted key between dots); a glTF material name fits many times.
inline constexpr size_t kMaxTomlKeyBytes = 1024;

// Throws InputError "FILE:LINE: what is wrong" for invalid UTF-8, nesting deeper than
// kMaxTomlDepth or a key longer than kMaxTomlKeyBytes. Does not check TOML syntax beyond what
// it needs to find keys, strings and comments; toml++ reports the rest.
void checkTomlText(std::string_view text, const std::string& fileName);

// checkTomlText, then toml::parse; a parse error becomes InputError "FILE:LINE: what".
toml::table parseToml(std::string_view text, const std::string& fileName);

} // namespace lumar
