// How many GL objects of each kind are alive in the current context, counted by asking GL
// (glIs*) about every name it has handed out so far: the soak (scripts/soak.sh) samples it
// once a second through status.json to see that reloads and long runs leak none. It asks GL
// rather than counting in the owners (gles_renderer/gl/gl_object.h), so it also sees names a leak made
// outside them. Mesa hands out increasing names (a freed name is not reused before the 32-bit
// space wraps), so the name a fresh glGen*/glCreate* returns bounds the scan; one sample costs
// one glIs* call per name ever made (a few hundred in lumar: microseconds).
#pragma once

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

namespace lumar {

// {"textures", n}, {"buffers", n}, {"vertex_arrays", n}, {"framebuffers", n},
// {"renderbuffers", n}, {"samplers", n}, {"programs", n}, {"shaders", n}. A context must be
// current. Names beyond kMaxGlCensusNames per kind are not scanned (reported as counted).
std::vector<std::pair<std::string, int64_t>> glObjectCensus();

inline constexpr uint32_t kMaxGlCensusNames = 1u << 16;

} // namespace lumar
