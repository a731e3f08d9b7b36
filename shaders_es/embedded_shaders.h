// GLSL ES 3.00 sources from shaders_es/, validated by glslangValidator at build time and
// embedded into the binary (the build generates the definitions).
#pragma once

#include <span>
#include <string_view>

namespace lumar::shaders {

struct Entry {
    std::string_view name; // file name, e.g. "mesh.frag"
    std::string_view text;
};

std::span<const Entry> all();

// The source of shader `name`, or an empty view when there is none.
std::string_view source(std::string_view name);

} // namespace lumar::shaders
