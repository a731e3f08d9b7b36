#include "object_animation.h"

#include <string>

#include "core/error.h"
#include "gles_renderer/assets/gltf_animation.h"
#include "gles_renderer/assets/gltf_rig.h"

namespace lumar {
namespace {

// "'Survey', 'Walk', 'Run'" (unnamed ones by index), for messages.
std::string describeAnimations(const GltfRig& rig)
{
    std::string names;
    for (size_t a = 0; a < rig.animations.size(); ++a) {
        names += names.empty() ? "" : ", ";
        names += rig.animations[a].name.empty() ? std::to_string(a) + " (unnamed)" : "'" + rig.animations[a].name + "'";
    }
    return names;
}

} // namespace

ObjectAnimation resolveObjectAnimation(const ObjectConfig& object, const GltfModel& model)
{
    ObjectAnimation resolved;
    resolved.loop = object.loop;
    resolved.speed = object.speed;
    const std::string where = object.model.string() + ": object '" + object.name + "'";
    const GltfRig* rig = model.rig.get();
    const bool explicitChoice = object.animationIndex >= 0 ||
                                (!object.animation.empty() && object.animation != "all" && object.animation != "none");
    if (!rig || rig->animations.empty()) {
        if (explicitChoice)
            throw InputError(
                where + ": animation " +
                (object.animationIndex >= 0 ? std::to_string(object.animationIndex) : "'" + object.animation + "'") +
                " asked for, but the model has no animations");
        return resolved;
    }
    const size_t count = rig->animations.size();
    if (object.animation == "none")
        return resolved;
    if (object.animationIndex >= 0) {
        if (size_t(object.animationIndex) >= count)
            throw InputError(where + ": animation " + std::to_string(object.animationIndex) +
                             " does not exist (the model has " + std::to_string(count) + ": " +
                             describeAnimations(*rig) + ")");
        resolved.animations.push_back(object.animationIndex);
    } else if (object.animation == "all") {
        for (size_t a = 0; a < count; ++a)
            resolved.animations.push_back(int(a));
    } else if (object.animation.empty()) {
        resolved.animations.push_back(0);
    } else {
        for (size_t a = 0; a < count && resolved.animations.empty(); ++a)
            if (rig->animations[a].name == object.animation)
                resolved.animations.push_back(int(a));
        if (resolved.animations.empty())
            throw InputError(where + ": the model has no animation '" + object.animation + "' (it has " +
                             describeAnimations(*rig) + ")");
    }
    for (const int a : resolved.animations)
        resolved.durations.push_back(double(rig->animations[size_t(a)].duration));
    return resolved;
}

void clipTimesAt(const ObjectAnimation& animation, double sceneSeconds, std::vector<ClipTime>& clips)
{
    clips.clear();
    for (size_t i = 0; i < animation.animations.size(); ++i)
        clips.push_back({animation.animations[i],
                         clipSeconds(sceneSeconds, animation.durations[i], animation.speed, animation.loop)});
}

} // namespace lumar
