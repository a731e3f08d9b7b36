// glTF 2.0 animations as plain data (§3.11), and their evaluation: keyframe samplers with
// STEP, LINEAR (spherical for rotations) and CUBICSPLINE interpolation, and the clip time a
// scene time stands for (speed, loop). No tinygltf here: gltf_rig.h reads them from a file.
#pragma once

#include <span>
#include <string>
#include <vector>

#include <glm/glm.hpp>
#include <glm/gtc/quaternion.hpp>

namespace lumar {

enum class Interpolation { Step, Linear, CubicSpline };
enum class AnimatedProperty { Translation, Rotation, Scale, Weights };

struct AnimationSampler {
    Interpolation interpolation = Interpolation::Linear;
    std::vector<float> times; // seconds, strictly increasing, at least one
    // `components` floats per keyframe (rotations: x, y, z, w as glTF stores them); with
    // CubicSpline three such elements per keyframe: in-tangent, value, out-tangent.
    std::vector<float> values;
    int components = 0;
};

struct AnimationChannel {
    int sampler = 0; // index into Animation::samplers
    int node = 0;    // index into GltfRig::nodes
    AnimatedProperty property = AnimatedProperty::Translation;
};

struct Animation {
    std::string name; // may be empty
    std::vector<AnimationSampler> samplers;
    std::vector<AnimationChannel> channels;
    float duration = 0.0f; // the last keyframe time of any sampler: the clip runs over [0, duration]
};

// The sampler's value at `seconds` into `out` (sampler.components floats). Before the first
// keyframe the first value holds, after the last the last one. `rotation`: the values are
// quaternions, LINEAR slerps along the shorter arc and every result is unit length.
void sampleAnimation(const AnimationSampler& sampler, float seconds, bool rotation, std::span<float> out);

// Spherical linear interpolation from `a` to `b` along the shorter arc (glTF 2.0 Appendix C).
glm::quat slerpShortest(const glm::quat& a, const glm::quat& b, float t);

// Seconds into a clip of `duration` seconds when the scene has run `sceneSeconds` at `speed`
// times real time: wrapped into [0, duration) when `loop`, else held at the clip's end.
double clipSeconds(double sceneSeconds, double duration, double speed, bool loop);

} // namespace lumar
