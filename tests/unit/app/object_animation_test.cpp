// Which clips an object plays ([[objects]] animation, loop, speed) resolved against its model,
// and the clip times the renderer poses it at (issue 20).
#include <memory>

#include <gtest/gtest.h>

#include "core/error.h"
#include "gles_renderer/assets/gltf_rig.h"
#include "object_animation.h"

namespace lumar {
namespace {

GltfModel modelWithClips()
{
    auto rig = std::make_shared<GltfRig>();
    for (const auto& [name, duration] : {std::pair{"Survey", 3.0f}, std::pair{"Walk", 1.0f}, std::pair{"", 2.0f}}) {
        Animation& a = rig->animations.emplace_back();
        a.name = name;
        a.duration = duration;
    }
    GltfModel model;
    model.file = "fox.glb";
    model.rig = rig;
    return model;
}

ObjectConfig object(const std::string& animation, int index = -1)
{
    ObjectConfig o;
    o.name = "fox";
    o.model = "fox.glb";
    o.animation = animation;
    o.animationIndex = index;
    return o;
}

TEST(ObjectAnimation, DefaultIsTheFirstClip)
{
    const ObjectAnimation a = resolveObjectAnimation(object(""), modelWithClips());
    ASSERT_EQ(a.animations, std::vector<int>{0});
    EXPECT_EQ(a.durations, std::vector<double>{3.0});
    EXPECT_TRUE(a.loop);
}

TEST(ObjectAnimation, NamesIndicesAllAndNone)
{
    EXPECT_EQ(resolveObjectAnimation(object("Walk"), modelWithClips()).animations, std::vector<int>{1});
    EXPECT_EQ(resolveObjectAnimation(object("", 2), modelWithClips()).animations, std::vector<int>{2});
    EXPECT_EQ(resolveObjectAnimation(object("all"), modelWithClips()).animations, (std::vector<int>{0, 1, 2}));
    EXPECT_FALSE(resolveObjectAnimation(object("none"), modelWithClips()).plays());
    // A still model: the default and "none" play nothing.
    EXPECT_FALSE(resolveObjectAnimation(object(""), GltfModel{}).plays());
    EXPECT_FALSE(resolveObjectAnimation(object("all"), GltfModel{}).plays());
}

TEST(ObjectAnimation, UnknownNamesListTheModelsClips)
{
    try {
        (void)resolveObjectAnimation(object("Run"), modelWithClips());
        FAIL() << "expected InputError";
    } catch (const InputError& e) {
        EXPECT_STREQ(e.what(), "fox.glb: object 'fox': the model has no animation 'Run' (it has 'Survey', 'Walk', 2 "
                               "(unnamed))");
    }
    EXPECT_THROW((void)resolveObjectAnimation(object("", 3), modelWithClips()), InputError);
    EXPECT_THROW((void)resolveObjectAnimation(object("Walk"), GltfModel{}), InputError);
}

TEST(ObjectAnimation, ClipTimesFollowSpeedAndLoop)
{
    ObjectAnimation a = resolveObjectAnimation(object("all"), modelWithClips());
    std::vector<ClipTime> clips;
    clipTimesAt(a, 3.5, clips);
    ASSERT_EQ(clips.size(), 3u);
    EXPECT_NEAR(clips[0].seconds, 0.5, 1e-12); // each clip loops over its own length
    EXPECT_NEAR(clips[1].seconds, 0.5, 1e-12);
    EXPECT_NEAR(clips[2].seconds, 1.5, 1e-12);
    a.loop = false;
    a.speed = 0.5;
    clipTimesAt(a, 3.5, clips);
    EXPECT_NEAR(clips[0].seconds, 1.75, 1e-12);
    EXPECT_NEAR(clips[1].seconds, 1.0, 1e-12); // held at its end
}

} // namespace
} // namespace lumar
