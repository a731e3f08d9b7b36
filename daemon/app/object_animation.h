// Which of an object's glTF animations play, and how fast ([[objects]] animation, loop,
// speed), resolved against its loaded model; and the clip times the renderer poses it at.
//
// Default: the model's first animation, looping. glTF names no default animation, and a
// model exported with one (a waving mascot, a turning product) is expected to move; "none"
// keeps it still, "all" plays every clip at once (each looping over its own length), for
// files whose parts were exported as separate clips.
#pragma once

#include <vector>

#include "config/config.h"
#include "gles_renderer/assets/gltf_model.h"
#include "gles_renderer/assets/model_pose.h"

namespace lumar {

struct ObjectAnimation {
    std::vector<int> animations; // indices into the model's rig; empty: nothing plays
    std::vector<double> durations;
    bool loop = true;
    double speed = 1.0;
    [[nodiscard]] bool plays() const { return !animations.empty(); }
};

// Throws InputError "MODEL: object 'NAME': ..." for a name or index the model does not have
// (naming the ones it has), or an animation asked for by a model without animations.
ObjectAnimation resolveObjectAnimation(const ObjectConfig& object, const GltfModel& model);

// The clips of `animation` at `sceneSeconds` since the scene started, into `clips`.
void clipTimesAt(const ObjectAnimation& animation, double sceneSeconds, std::vector<ClipTime>& clips);

} // namespace lumar
