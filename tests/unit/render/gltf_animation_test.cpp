// glTF animation (issue 20): keyframe interpolation against hand-computed values, quaternion
// slerp, skinning and morphing maths, models posed from files (a generated bending bar, the
// Khronos SimpleSkin and SimpleMorph), and bad rigs rejected in one line naming the file.
#include <cmath>
#include <string>
#include <vector>

#include <glm/gtc/matrix_transform.hpp>
#include <gtest/gtest.h>

#include "animated_gltf.h"
#include "gles_renderer/assets/gltf_animation.h"
#include "gles_renderer/assets/gltf_model.h"
#include "gles_renderer/assets/gltf_rig.h"
#include "gles_renderer/assets/gltf_skin.h"
#include "gles_renderer/assets/model_pose.h"
#include "render_test_support.h"

namespace lumar {
namespace {

using test::ScratchDir;

constexpr float kTolerance = 1e-5f;

std::vector<float> sample(const AnimationSampler& sampler, float t, bool rotation = false)
{
    std::vector<float> out(size_t(sampler.components));
    sampleAnimation(sampler, t, rotation, out);
    return out;
}

void expectNear(const glm::vec3& actual, const glm::vec3& expected, float tolerance = kTolerance)
{
    EXPECT_NEAR(actual.x, expected.x, tolerance);
    EXPECT_NEAR(actual.y, expected.y, tolerance);
    EXPECT_NEAR(actual.z, expected.z, tolerance);
}

TEST(AnimationSampler, LinearInterpolatesAndHoldsOutsideTheKeyframes)
{
    AnimationSampler s;
    s.components = 3;
    s.times = {0.0f, 1.0f, 3.0f};
    s.values = {0, 0, 0, 2, 4, 6, 4, 4, 4};
    EXPECT_EQ(sample(s, 0.5f), (std::vector<float>{1, 2, 3}));
    EXPECT_EQ(sample(s, 2.0f), (std::vector<float>{3, 4, 5}));
    EXPECT_EQ(sample(s, 1.0f), (std::vector<float>{2, 4, 6}));
    EXPECT_EQ(sample(s, -1.0f), (std::vector<float>{0, 0, 0}));
    EXPECT_EQ(sample(s, 10.0f), (std::vector<float>{4, 4, 4}));
}

TEST(AnimationSampler, StepHoldsEachKeyframeUntilTheNext)
{
    AnimationSampler s;
    s.interpolation = Interpolation::Step;
    s.components = 1;
    s.times = {0.0f, 1.0f, 2.0f};
    s.values = {5, 7, 9};
    EXPECT_EQ(sample(s, 0.99f)[0], 5.0f);
    EXPECT_EQ(sample(s, 1.0f)[0], 7.0f);
    EXPECT_EQ(sample(s, 1.7f)[0], 7.0f);
    EXPECT_EQ(sample(s, 2.5f)[0], 9.0f);
}

TEST(AnimationSampler, CubicSplineIsTheHermiteCurveOfTheSpecification)
{
    // Keyframes at 0 s and 2 s: (in 0, value 0, out 1) and (in 3, value 1, out 0).
    // p(s) = h00 v0 + h10 td b0 + h01 v1 + h11 td a1 with td = 2, b0 = 1, a1 = 3:
    // s = 0.25: 0.140625 * 2 + 0.15625 - 0.046875 * 6 = 0.15625; s = 0.5: 0.25 + 0.5 - 0.75 = 0.
    AnimationSampler s;
    s.interpolation = Interpolation::CubicSpline;
    s.components = 1;
    s.times = {0.0f, 2.0f};
    s.values = {0, 0, 1, 3, 1, 0};
    EXPECT_NEAR(sample(s, 0.5f)[0], 0.15625f, kTolerance);
    EXPECT_NEAR(sample(s, 1.0f)[0], 0.0f, kTolerance);
    EXPECT_NEAR(sample(s, 0.0f)[0], 0.0f, kTolerance);
    EXPECT_NEAR(sample(s, 2.0f)[0], 1.0f, kTolerance);
    EXPECT_NEAR(sample(s, 5.0f)[0], 1.0f, kTolerance); // the last value, not a tangent
}

TEST(AnimationSampler, LinearRotationsSlerpAlongTheShorterArc)
{
    const float h = std::sqrt(0.5f);
    AnimationSampler s;
    s.components = 4;
    s.times = {0.0f, 1.0f};
    s.values = {0, 0, 0, 1, 0, 0, h, h}; // identity, then 90 degrees about z
    const std::vector<float> q = sample(s, 0.5f, true);
    const float angle = glm::radians(22.5f);
    EXPECT_NEAR(q[2], std::sin(angle), kTolerance);
    EXPECT_NEAR(q[3], std::cos(angle), kTolerance);
    // A third of the way: 30 degrees (a component-wise lerp would give 29.4 and not unit length).
    const std::vector<float> third = sample(s, 1.0f / 3.0f, true);
    EXPECT_NEAR(2.0f * std::atan2(third[2], third[3]), glm::radians(30.0f), 1e-4f);
    // The same end rotation stored as -q: the shorter way, the same 45-degree midpoint.
    s.values = {0, 0, 0, 1, 0, 0, -h, -h};
    const std::vector<float> flipped = sample(s, 0.5f, true);
    const glm::quat r(flipped[3], flipped[0], flipped[1], flipped[2]);
    expectNear(r * glm::vec3(1, 0, 0), glm::vec3(std::cos(glm::radians(45.0f)), std::sin(glm::radians(45.0f)), 0));
    EXPECT_NEAR(glm::length(r), 1.0f, kTolerance);
}

TEST(AnimationSampler, ClipTimeLoopsOrHolds)
{
    EXPECT_NEAR(clipSeconds(2.5, 1.0, 1.0, true), 0.5, 1e-12);
    EXPECT_NEAR(clipSeconds(2.5, 2.0, 2.0, true), 1.0, 1e-12);
    EXPECT_NEAR(clipSeconds(2.5, 1.0, 1.0, false), 1.0, 1e-12);
    EXPECT_NEAR(clipSeconds(0.25, 1.0, 1.0, false), 0.25, 1e-12);
    EXPECT_EQ(clipSeconds(7.0, 0.0, 1.0, true), 0.0); // a one-keyframe clip
    EXPECT_EQ(clipSeconds(7.0, 1.0, 0.0, true), 0.0); // speed 0: the first pose
}

TEST(Skinning, TwoJointChainBentNinetyDegrees)
{
    // Hip at the origin, knee at (0, 1, 0) turned 90 degrees about z; the knee's inverse bind
    // matrix undoes its rest translation.
    const glm::mat4 knee = glm::translate(glm::mat4(1.0f), glm::vec3(0, 1, 0)) *
                           glm::rotate(glm::mat4(1.0f), glm::radians(90.0f), {0, 0, 1});
    const glm::mat4 inverseBind = glm::translate(glm::mat4(1.0f), glm::vec3(0, -1, 0));
    const std::vector<glm::mat4> joints = {glm::mat4(1.0f), knee * inverseBind};
    JointInfluences set;
    set.joints = {{1, 0, 0, 0}, {0, 1, 0, 0}, {0, 0, 0, 0}};
    set.weights = {{1, 0, 0, 0}, {0.5f, 0.5f, 0, 0}, {0, 0, 0, 0}};
    std::vector<glm::vec3> positions = {{0, 2, 0}, {0, 1.5f, 0}, {3, 3, 3}};
    std::vector<glm::vec3> normals = {{1, 0, 0}, {1, 0, 0}, {0, 1, 0}};
    std::vector<glm::vec4> tangents = {{0, 1, 0, -1}, {0, 1, 0, 1}, {1, 0, 0, 1}};
    skinVertices(joints, std::vector<JointInfluences>{set}, {positions, normals, tangents},
                 {positions, normals, tangents});
    expectNear(positions[0], {-1, 1, 0}); // one unit past the knee, turned left
    expectNear(normals[0], {0, 1, 0});    // turned with it
    expectNear(glm::vec3(tangents[0]), {-1, 0, 0});
    EXPECT_EQ(tangents[0].w, -1.0f);              // handedness kept
    expectNear(positions[1], {-0.25f, 1.25f, 0}); // halfway between (0, 1.5) and (-0.5, 1)
    EXPECT_NEAR(glm::length(normals[1]), 1.0f, kTolerance);
    expectNear(positions[2], {3, 3, 3}); // no influence: left alone
}

TEST(Skinning, WeightsNotSummingToOneAreRenormalised)
{
    const std::vector<glm::mat4> joints = {glm::translate(glm::mat4(1.0f), glm::vec3(2, 0, 0)),
                                           glm::translate(glm::mat4(1.0f), glm::vec3(0, 4, 0))};
    JointInfluences set;
    set.joints = {{0, 1, 0, 0}};
    set.weights = {{0.25f, 0.25f, 0, 0}}; // as 0.5 / 0.5
    std::vector<glm::vec3> positions = {{0, 0, 0}}, normals = {{0, 0, 1}};
    skinVertices(joints, std::vector<JointInfluences>{set}, {positions, normals, {}}, {positions, normals, {}});
    expectNear(positions[0], {1, 2, 0});
}

TEST(MorphTargets, WeightedDisplacementsAdd)
{
    const std::vector<glm::vec3> basePositions = {{0, 0, 0}, {1, 0, 0}};
    const std::vector<glm::vec3> baseNormals = {{0, 0, 1}, {0, 0, 1}};
    std::vector<MorphTarget> targets(2);
    targets[0].positions = {{0, 2, 0}, {0, 2, 0}};
    targets[0].normals = {{0, 2, -1}, {0, 0, 0}};
    targets[1].positions = {{4, 0, 0}, {0, 0, 4}};
    std::vector<glm::vec3> positions(2), normals(2);
    const std::vector<float> weights = {0.5f, 0.25f};
    applyMorphTargets({basePositions, baseNormals, {}}, targets, weights, {positions, normals, {}});
    expectNear(positions[0], {1, 1, 0});
    expectNear(positions[1], {1, 1, 1});
    expectNear(normals[0], glm::normalize(glm::vec3(0, 1, 0.5f)));
    expectNear(normals[1], {0, 0, 1});
}

// The posed model's vertex nearest to `p` (the test models are tiny).
glm::vec3 nearestVertex(const ModelPoser& poser, size_t primitive, const glm::vec3& p)
{
    glm::vec3 best = poser.positions(primitive).front();
    for (const glm::vec3& v : poser.positions(primitive))
        if (glm::distance(v, p) < glm::distance(best, p))
            best = v;
    return glm::vec3(poser.modelFromMesh(primitive) * glm::vec4(best, 1.0f));
}

TEST(GltfAnimation, GeneratedBarBendsAtTheKnee)
{
    ScratchDir dir;
    const GltfModel model = loadGltfModel(test::bendingBar().write(dir, "bar"));
    ASSERT_TRUE(model.rig);
    ASSERT_EQ(model.rig->animations.size(), 1u);
    EXPECT_EQ(model.rig->animations[0].name, "bend");
    EXPECT_FLOAT_EQ(model.rig->animations[0].duration, 1.0f);
    expectNear(model.boundsMax, {0.1f, 2, 0}); // the rest pose
    ModelPoser poser(model.rig);
    ASSERT_TRUE(poser.deforms(0));
    const ClipTime bent[] = {{0, 1.0}};
    poser.pose(bent);
    expectNear(nearestVertex(poser, 0, {-1, 0.9f, 0}), {-1, 0.9f, 0});
    expectNear(nearestVertex(poser, 0, {-1, 1.1f, 0}), {-1, 1.1f, 0});
    expectNear(nearestVertex(poser, 0, {0.1f, 1, 0}), {0.1f, 1, 0}); // the hip's half stays
    expectNear(poser.boundsMin(), {-1, 0, 0});
    expectNear(poser.boundsMax(), {0.1f, 1.1f, 0});
    // Half way: 45 degrees, the bar's top centre at the knee + (-sin 45, cos 45).
    const ClipTime half[] = {{0, 0.5}};
    poser.pose(half);
    const float s = std::sqrt(0.5f);
    const glm::vec3 top = 0.5f * (nearestVertex(poser, 0, {-s - 0.07f, 1 + s - 0.07f, 0}) +
                                  nearestVertex(poser, 0, {-s + 0.07f, 1 + s + 0.07f, 0}));
    expectNear(top, {-s, 1 + s, 0});
    EXPECT_THROW(poser.pose(std::vector<ClipTime>{{1, 0.0}}), InputError);
}

TEST(GltfAnimation, ModelWithoutAnimationsIsPosedOnceAndKeepsNoRig)
{
    ScratchDir dir;
    test::MiniGltf g = test::bendingBar();
    // The knee bent 90 degrees at rest, no animation: the loaded vertices show the bend.
    g.nodes =
        R"({"name":"hip","children":[1,2]},{"name":"knee","translation":[0,1,0],"rotation":[0,0,0.70710678,0.70710678]},{"mesh":0,"skin":0})";
    g.extra = R"(,"skins":[{"joints":[0,1],"inverseBindMatrices":5}])";
    const GltfModel model = loadGltfModel(g.write(dir, "bent"));
    EXPECT_FALSE(model.rig);
    expectNear(model.boundsMin, {-1, 0, 0});
    expectNear(model.boundsMax, {0.1f, 1.1f, 0});
}

std::filesystem::path khronos(const std::string& name)
{
    return test::testDataPath("khronos/" + name + "/" + name + ".gltf");
}

TEST(GltfAnimation, KhronosSimpleMorphDefaultWeightsAndAnimation)
{
    // SimpleMorph: a triangle-pair with two targets at default weights 0.5 / 0.5 whose
    // weights animation runs from (0, 0) at 0 s to (1, 0) at 1 s, (0, 1) at 2 s ...
    const GltfModel model = loadGltfModel(khronos("SimpleMorph"));
    ASSERT_TRUE(model.rig);
    ModelPoser poser(model.rig);
    ASSERT_TRUE(poser.deforms(0));
    const auto& rest = model.rig->primitives[0].deformation;
    ASSERT_EQ(rest->targets.size(), 2u);
    // The rest pose (default weights) is what the loader baked.
    for (size_t v = 0; v < rest->positions.size(); ++v) {
        const glm::vec3 expected =
            rest->positions[v] + 0.5f * rest->targets[0].positions[v] + 0.5f * rest->targets[1].positions[v];
        expectNear(model.primitives[0].positions[v], expected);
    }
    const Animation& animation = model.rig->animations[0];
    ASSERT_EQ(animation.channels.size(), 1u);
    const AnimationSampler& sampler = animation.samplers[size_t(animation.channels[0].sampler)];
    for (size_t k = 0; k < sampler.times.size(); ++k) {
        const ClipTime at[] = {{0, double(sampler.times[k])}};
        poser.pose(at);
        const float w0 = sampler.values[2 * k], w1 = sampler.values[2 * k + 1];
        for (size_t v = 0; v < rest->positions.size(); ++v)
            expectNear(poser.positions(0)[v],
                       rest->positions[v] + w0 * rest->targets[0].positions[v] + w1 * rest->targets[1].positions[v]);
    }
}

TEST(GltfAnimation, KhronosSimpleSkinJointMovesItsVertices)
{
    // SimpleSkin: a strip skinned to two joints; the second joint turns about z, to 90 degrees
    // from 1 s to 1.5 s and back, then to -90.
    const GltfModel model = loadGltfModel(khronos("SimpleSkin"));
    ASSERT_TRUE(model.rig);
    ModelPoser poser(model.rig);
    const glm::vec3 restMax = poser.boundsMax(), restMin = poser.boundsMin();
    expectNear(restMin, model.boundsMin);
    expectNear(restMax, model.boundsMax);
    // At the keyframe of largest rotation the strip's top swings sideways: its bounds widen
    // in x, and every posed vertex equals the skinning formula applied by hand.
    const ClipTime at[] = {{0, 1.25}}; // the joint turned 90 degrees (1 s to 1.5 s)
    poser.pose(at);
    EXPECT_GT(poser.boundsMax().x - poser.boundsMin().x, restMax.x - restMin.x + 0.2f);
    const GltfRig& rig = *model.rig;
    const RigSkin& skin = rig.skins[0];
    const PrimitiveDeformation& d = *rig.primitives[0].deformation;
    // Joint matrices by hand from the sampled rotation of the second joint at 1.25 s.
    const Animation& animation = rig.animations[0];
    std::vector<float> q(4);
    for (const AnimationChannel& channel : animation.channels)
        if (channel.node == skin.joints[1] && channel.property == AnimatedProperty::Rotation)
            sampleAnimation(animation.samplers[size_t(channel.sampler)], 1.25f, true, q);
    const RigNode& second = rig.nodes[size_t(skin.joints[1])];
    const glm::mat4 modelFromSecond =
        glm::translate(glm::mat4(1.0f), second.translation) * glm::mat4_cast(glm::quat(q[3], q[0], q[1], q[2]));
    ASSERT_EQ(second.parent, skin.joints[0]);
    const glm::mat4 modelFromFirst = glm::translate(glm::mat4(1.0f), rig.nodes[size_t(skin.joints[0])].translation);
    const glm::mat4 j0 = modelFromFirst * skin.inverseBindMatrices[0];
    const glm::mat4 j1 = modelFromFirst * modelFromSecond * skin.inverseBindMatrices[1];
    for (size_t v = 0; v < d.positions.size(); ++v) {
        const glm::vec4 w = d.influences[0].weights[v];
        const glm::u16vec4 j = d.influences[0].joints[v];
        glm::mat4 m(0.0f);
        for (int c = 0; c < 4; ++c)
            m += w[c] * (j[c] == 0 ? j0 : j1);
        expectNear(poser.positions(0)[v], glm::vec3(m * glm::vec4(d.positions[v], 1.0f)), 1e-4f);
    }
}

// Bad rigs: one line naming the file and what is wrong, never a crash.
std::string rejected(const test::MiniGltf& g, const std::string& name)
{
    ScratchDir dir;
    const auto file = g.write(dir, name);
    return test::expectInputErrorNamingFile([&] { (void)loadGltfModel(file); }, file);
}

TEST(GltfAnimationBadInput, SkinJointThatIsNotANode)
{
    test::MiniGltf g = test::bendingBar();
    g.extra = R"(,"skins":[{"joints":[0,7],"inverseBindMatrices":5}])";
    EXPECT_NE(rejected(g, "joint").find("skin 0: joint 7 is not a node"), std::string::npos);
}

TEST(GltfAnimationBadInput, ChannelTargetingAMissingNode)
{
    test::MiniGltf g = test::bendingBar();
    const std::string good = R"("target":{"node":1,)";
    g.extra.replace(g.extra.find(good), good.size(), R"("target":{"node":9,)");
    EXPECT_NE(rejected(g, "channel").find("animation 0 channel 0 targets node 9, which does not exist"),
              std::string::npos);
}

TEST(GltfAnimationBadInput, SamplerInputOutputMismatch)
{
    test::MiniGltf g = test::bendingBar();
    // Two keyframe times, one rotation.
    const std::string rotations = R"({"bufferView":7,"componentType":5126,"count":2)";
    g.accessors.replace(g.accessors.find(rotations), rotations.size(),
                        R"({"bufferView":7,"componentType":5126,"count":1)");
    const std::string message = rejected(g, "counts");
    EXPECT_NE(message.find("animation 0 sampler 0: 2 keyframe times but 1 output elements"), std::string::npos)
        << message;
}

TEST(GltfAnimationBadInput, NonIncreasingKeyframeTimes)
{
    const std::string message = rejected(test::bendingBar(0.0f), "times");
    EXPECT_NE(message.find("animation 0 sampler 0: keyframe times do not increase"), std::string::npos) << message;
}

TEST(GltfAnimationBadInput, JointIndexBeyondTheSkin)
{
    test::MiniGltf g = test::bendingBar();
    g.extra = R"(,"skins":[{"joints":[0],"inverseBindMatrices":5}])"; // one joint; the top row names joint 1
    EXPECT_NE(rejected(g, "range").find("names joint 1, the skin has 1"), std::string::npos);
}

TEST(GltfAnimationBadInput, WeightsChannelWithoutMorphTargetsAndCycles)
{
    test::MiniGltf g = test::bendingBar();
    const std::string path = R"("path":"rotation")";
    g.extra.replace(g.extra.find(path), path.size(), R"("path":"weights")");
    EXPECT_NE(rejected(g, "weights").find("no mesh with morph targets"), std::string::npos);
    test::MiniGltf cycle = test::bendingBar();
    cycle.nodes =
        R"({"name":"hip","children":[1,2]},{"name":"knee","translation":[0,1,0],"children":[0]},{"mesh":0,"skin":0})";
    rejected(cycle, "cycle");
}

} // namespace
} // namespace lumar
