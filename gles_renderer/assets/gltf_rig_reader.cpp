#include "gles_renderer/assets/gltf_rig_reader.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <map>
#include <string>
#include <tuple>
#include <utility>

#include <glm/gtc/matrix_transform.hpp>

#include "core/error.h"
#include "core/log.h"
#include "gles_renderer/assets/gltf_accessors.h"

namespace lumar::gltf {
namespace {

// Budgets beside the loader's triangle and vertex limits (issue 16), far beyond any model
// we render (Fox's three clips hold 20k keyframe floats, CesiumMan's one 6k): every
// animation's keyframe data together, 64 MB as floats ...
constexpr size_t kMaxKeyframeFloats = size_t(1) << 24;
// ... every morph target's displacements together, 128 MB as floats ...
constexpr size_t kMaxMorphFloats = size_t(1) << 25;
// ... and JOINTS_n/WEIGHTS_n sets read per primitive: 16 influences per vertex.
constexpr int kMaxInfluenceSets = 4;

std::string str(size_t value)
{
    return std::to_string(value);
}

bool isNormalizedInteger(const tinygltf::Accessor& accessor)
{
    const int type = accessor.componentType;
    return accessor.normalized &&
           (type == TINYGLTF_COMPONENT_TYPE_BYTE || type == TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE ||
            type == TINYGLTF_COMPONENT_TYPE_SHORT || type == TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT);
}

// Reads an accessor whose component type `allowed` accepts; `what` names its use.
template <typename Allowed>
std::vector<float> readChecked(const tinygltf::Model& model, int index, int components, const std::string& what,
                               const char* expected, const Allowed& allowed)
{
    std::vector<float> values;
    try {
        values = readAccessorAsFloats(model, index, components);
    } catch (const InputError& e) {
        throw InputError(what + ": " + e.what());
    }
    const tinygltf::Accessor& accessor = model.accessors[size_t(index)];
    if (!allowed(accessor))
        throw InputError(what + ": accessor " + std::to_string(index) + " has componentType " +
                         std::to_string(accessor.componentType) + (accessor.normalized ? " (normalized)" : "") + ", " +
                         expected + " expected");
    return values;
}

bool isFloat(const tinygltf::Accessor& a)
{
    return a.componentType == TINYGLTF_COMPONENT_TYPE_FLOAT;
}

glm::vec3 vec3Or(const std::vector<double>& values, const glm::vec3& fallback, const std::string& what)
{
    if (values.empty())
        return fallback;
    if (values.size() != 3)
        throw InputError(what + " must have 3 numbers");
    const glm::dvec3 v(values[0], values[1], values[2]);
    if (!std::isfinite(v.x + v.y + v.z) || glm::any(glm::greaterThan(glm::abs(v), glm::dvec3(1e30))))
        throw InputError(what + " holds a non-finite or huge number");
    return glm::vec3(v);
}

RigNode restNode(const tinygltf::Node& node, const std::string& what)
{
    RigNode rest;
    if (!node.matrix.empty()) {
        if (node.matrix.size() != 16)
            throw InputError(what + ": matrix must have 16 numbers");
        glm::mat4 m(1.0f);
        for (int i = 0; i < 16; ++i) {
            const double v = node.matrix[size_t(i)];
            if (!(std::abs(v) < 1e30))
                throw InputError(what + ": matrix holds a non-finite or huge number");
            m[i / 4][i % 4] = float(v);
        }
        rest.matrix = m;
        return rest;
    }
    rest.translation = vec3Or(node.translation, glm::vec3(0.0f), what + " translation");
    rest.scale = vec3Or(node.scale, glm::vec3(1.0f), what + " scale");
    if (!node.rotation.empty()) {
        if (node.rotation.size() != 4)
            throw InputError(what + ": rotation must have 4 numbers");
        const glm::dquat q(node.rotation[3], node.rotation[0], node.rotation[1], node.rotation[2]);
        const double length = glm::length(q);
        if (!(length > 1e-12) || !std::isfinite(length))
            throw InputError(what + ": rotation is not a unit quaternion");
        rest.rotation = glm::quat(q / length);
    }
    return rest;
}

// Each node's parent, and an order with parents before children; a node with two parents
// or one in a cycle is an error (glTF 2.0 §3.5.3: the nodes form disjoint trees).
void readHierarchy(const tinygltf::Model& model, GltfRig& rig)
{
    const size_t n = model.nodes.size();
    rig.nodes.resize(n);
    for (size_t i = 0; i < n; ++i) {
        const std::string what = "node " + str(i);
        rig.nodes[i] = restNode(model.nodes[i], what);
    }
    std::vector<std::vector<int>> children(n);
    for (size_t i = 0; i < n; ++i) {
        for (const int child : model.nodes[i].children) {
            if (child < 0 || size_t(child) >= n)
                throw InputError("node " + str(i) + ": child " + std::to_string(child) + " does not exist");
            if (rig.nodes[size_t(child)].parent != -1 || size_t(child) == i)
                throw InputError("node " + std::to_string(child) +
                                 " has more than one parent: the node hierarchy is not a tree");
            rig.nodes[size_t(child)].parent = int(i);
            children[i].push_back(child);
        }
    }
    rig.order.reserve(n);
    for (size_t i = 0; i < n; ++i)
        if (rig.nodes[i].parent == -1)
            rig.order.push_back(int(i));
    for (size_t k = 0; k < rig.order.size(); ++k)
        for (const int child : children[size_t(rig.order[k])])
            rig.order.push_back(child);
    if (rig.order.size() != n) {
        std::vector<bool> reached(n, false);
        for (const int i : rig.order)
            reached[size_t(i)] = true;
        const size_t first = size_t(std::find(reached.begin(), reached.end(), false) - reached.begin());
        throw InputError("node " + str(first) + " is part of a cycle: the node hierarchy is not a tree");
    }
}

// Morph targets per mesh: all its primitives must have the same number (glTF 2.0 §3.7.2.2).
std::vector<size_t> meshTargetCounts(const tinygltf::Model& model)
{
    std::vector<size_t> counts(model.meshes.size(), 0);
    for (size_t m = 0; m < model.meshes.size(); ++m) {
        const auto& primitives = model.meshes[m].primitives;
        if (primitives.empty())
            continue;
        counts[m] = primitives.front().targets.size();
        for (size_t p = 1; p < primitives.size(); ++p)
            if (primitives[p].targets.size() != counts[m])
                throw InputError("mesh " + str(m) + ": its primitives have different numbers of morph targets (" +
                                 str(counts[m]) + " and " + str(primitives[p].targets.size()) + ")");
    }
    return counts;
}

void readRestWeights(const tinygltf::Model& model, const std::vector<size_t>& targetCounts, GltfRig& rig)
{
    for (size_t i = 0; i < model.nodes.size(); ++i) {
        const tinygltf::Node& node = model.nodes[i];
        if (node.mesh < 0 || size_t(node.mesh) >= model.meshes.size())
            continue; // the loader reports a missing mesh of a scene node
        const size_t targets = targetCounts[size_t(node.mesh)];
        if (targets == 0)
            continue;
        const std::vector<double>& meshWeights = model.meshes[size_t(node.mesh)].weights;
        const std::vector<double>& weights = node.weights.empty() ? meshWeights : node.weights;
        const std::string what = node.weights.empty() ? "mesh " + std::to_string(node.mesh) : "node " + str(i);
        if (!weights.empty() && weights.size() != targets)
            throw InputError(what + ": weights has " + str(weights.size()) + " numbers for " + str(targets) +
                             " morph targets");
        rig.nodes[i].weights.assign(targets, 0.0f);
        for (size_t k = 0; k < weights.size(); ++k) {
            if (!std::isfinite(weights[k]))
                throw InputError(what + ": weights holds a non-finite number");
            rig.nodes[i].weights[k] = float(weights[k]);
        }
    }
}

void readSkins(const tinygltf::Model& model, GltfRig& rig)
{
    for (size_t s = 0; s < model.skins.size(); ++s) {
        const tinygltf::Skin& source = model.skins[s];
        const std::string what = "skin " + str(s);
        if (source.joints.empty())
            throw InputError(what + " has no joints");
        if (source.joints.size() > size_t(std::numeric_limits<uint16_t>::max()) + 1)
            throw InputError(what + " has " + str(source.joints.size()) + " joints, more than JOINTS_n can name");
        RigSkin skin;
        for (const int joint : source.joints) {
            if (joint < 0 || size_t(joint) >= model.nodes.size())
                throw InputError(what + ": joint " + std::to_string(joint) + " is not a node (the file has " +
                                 str(model.nodes.size()) + ")");
            skin.joints.push_back(joint);
        }
        skin.inverseBindMatrices.assign(skin.joints.size(), glm::mat4(1.0f));
        if (source.inverseBindMatrices >= 0) {
            const std::vector<float> m =
                readChecked(model, source.inverseBindMatrices, 16, what + " inverseBindMatrices", "float", isFloat);
            if (m.size() / 16 < skin.joints.size())
                throw InputError(what + ": inverseBindMatrices has " + str(m.size() / 16) + " matrices for " +
                                 str(skin.joints.size()) + " joints");
            for (size_t j = 0; j < skin.joints.size(); ++j)
                for (int k = 0; k < 16; ++k)
                    skin.inverseBindMatrices[j][k / 4][k % 4] = m[j * 16 + size_t(k)];
        }
        rig.skins.push_back(std::move(skin));
    }
}

std::vector<glm::vec3> readTargetAttribute(const tinygltf::Model& model, const std::map<std::string, int>& target,
                                           const char* name, size_t vertexCount, const std::string& what)
{
    const auto found = target.find(name);
    if (found == target.end())
        return {};
    const std::vector<float> flat =
        readChecked(model, found->second, 3, what + " " + name, "any", [](const tinygltf::Accessor&) { return true; });
    if (flat.size() != vertexCount * 3)
        throw InputError(what + " " + name + " has " + str(flat.size() / 3) + " elements, POSITION has " +
                         str(vertexCount));
    std::vector<glm::vec3> out(vertexCount);
    for (size_t i = 0; i < vertexCount; ++i)
        out[i] = {flat[3 * i], flat[3 * i + 1], flat[3 * i + 2]};
    return out;
}

std::vector<JointInfluences> readInfluences(const tinygltf::Model& model, const tinygltf::Primitive& source,
                                            size_t vertexCount, size_t jointCount, const std::string& what)
{
    std::vector<JointInfluences> sets;
    for (int set = 0; set < kMaxInfluenceSets; ++set) {
        const std::string jointsName = "JOINTS_" + std::to_string(set), weightsName = "WEIGHTS_" + std::to_string(set);
        const auto joints = source.attributes.find(jointsName);
        const auto weights = source.attributes.find(weightsName);
        if (joints == source.attributes.end() && weights == source.attributes.end())
            break;
        if (joints == source.attributes.end() || weights == source.attributes.end())
            throw InputError(what + ": " +
                             (joints == source.attributes.end() ? weightsName + " without " + jointsName
                                                                : jointsName + " without " + weightsName));
        const std::vector<float> j =
            readChecked(model, joints->second, 4, what + " " + jointsName, "unsigned byte or short",
                        [](const tinygltf::Accessor& a) {
                            return !a.normalized && (a.componentType == TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE ||
                                                     a.componentType == TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT);
                        });
        const std::vector<float> w =
            readChecked(model, weights->second, 4, what + " " + weightsName,
                        "float or normalized unsigned byte or short", [](const tinygltf::Accessor& a) {
                            return isFloat(a) || (isNormalizedInteger(a) &&
                                                  (a.componentType == TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE ||
                                                   a.componentType == TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT));
                        });
        if (j.size() != vertexCount * 4 || w.size() != vertexCount * 4)
            throw InputError(what + ": " + jointsName + " and " + weightsName + " have " + str(j.size() / 4) + " and " +
                             str(w.size() / 4) + " elements, POSITION has " + str(vertexCount));
        JointInfluences influences;
        influences.joints.resize(vertexCount);
        influences.weights.resize(vertexCount);
        for (size_t v = 0; v < vertexCount; ++v) {
            for (int c = 0; c < 4; ++c) {
                const size_t k = v * 4 + size_t(c);
                float weight = w[k];
                uint16_t joint = uint16_t(j[k]); // an unsigned byte or short: exact
                if (!(weight >= 0.0f))
                    throw InputError(what + ": " + weightsName + " vertex " + str(v) + " has a negative weight");
                if (joint >= jointCount) {
                    // An unused slot may name any joint; a used one must exist.
                    if (weight != 0.0f)
                        throw InputError(what + ": " + jointsName + " vertex " + str(v) + " names joint " +
                                         std::to_string(joint) + ", the skin has " + str(jointCount));
                    joint = 0;
                }
                influences.joints[v][c] = joint;
                influences.weights[v][c] = weight;
            }
        }
        sets.push_back(std::move(influences));
    }
    return sets;
}

// What deforms an instance of a mesh primitive: its joint influences where its node has a
// skin, its morph targets. Null when neither.
std::shared_ptr<const PrimitiveDeformation> readDeformation(const tinygltf::Model& model,
                                                            const GltfPrimitive& primitive,
                                                            const tinygltf::Primitive& source, const RigSkin* skin,
                                                            size_t& morphFloats, const std::string& what)
{
    auto deformation = std::make_shared<PrimitiveDeformation>();
    const size_t n = primitive.positions.size();
    if (skin)
        deformation->influences = readInfluences(model, source, n, skin->joints.size(), what);
    for (size_t t = 0; t < source.targets.size(); ++t) {
        const std::string targetWhat = what + " morph target " + str(t);
        MorphTarget target;
        target.positions = readTargetAttribute(model, source.targets[t], "POSITION", n, targetWhat);
        target.normals = readTargetAttribute(model, source.targets[t], "NORMAL", n, targetWhat);
        target.tangents = readTargetAttribute(model, source.targets[t], "TANGENT", n, targetWhat);
        morphFloats += 3 * (target.positions.size() + target.normals.size() + target.tangents.size());
        if (morphFloats > kMaxMorphFloats)
            throw InputError("the morph targets hold more than " + str(kMaxMorphFloats) + " numbers");
        deformation->targets.push_back(std::move(target));
    }
    if (deformation->influences.empty() && deformation->targets.empty())
        return nullptr;
    deformation->positions = primitive.positions;
    deformation->normals = primitive.normals;
    deformation->tangents = primitive.tangents;
    return deformation;
}

glm::mat4 restLocal(const RigNode& node)
{
    if (node.matrix)
        return *node.matrix;
    return glm::translate(glm::mat4(1.0f), node.translation) * glm::mat4_cast(node.rotation) *
           glm::scale(glm::mat4(1.0f), node.scale);
}

void readPrimitives(const tinygltf::Model& model, const std::vector<GltfPrimitive>& primitives, GltfRig& rig)
{
    std::vector<glm::mat4> modelFromNode(rig.nodes.size());
    for (const int i : rig.order) {
        const RigNode& node = rig.nodes[size_t(i)];
        modelFromNode[size_t(i)] =
            node.parent >= 0 ? modelFromNode[size_t(node.parent)] * restLocal(node) : restLocal(node);
    }
    size_t morphFloats = 0;
    // Instances of one mesh primitive under one skin share their deformation.
    std::map<std::tuple<int, int, int>, std::shared_ptr<const PrimitiveDeformation>> shared;
    for (size_t i = 0; i < primitives.size(); ++i) {
        const GltfPrimitive& primitive = primitives[i];
        RiggedPrimitive& rigged = rig.primitives.emplace_back();
        rigged.node = primitive.node;
        if (primitive.node < 0 || size_t(primitive.node) >= model.nodes.size())
            throw InputError("primitive " + str(i) + " has no node to move it");
        const tinygltf::Node& node = model.nodes[size_t(primitive.node)];
        const int mesh = node.mesh;
        if (mesh < 0 || size_t(mesh) >= model.meshes.size() || primitive.meshPrimitive < 0 ||
            size_t(primitive.meshPrimitive) >= model.meshes[size_t(mesh)].primitives.size())
            throw InputError("primitive " + str(i) + " has no mesh primitive");
        if (node.skin < -1 || node.skin >= int(rig.skins.size()))
            throw InputError("node " + std::to_string(primitive.node) + ": skin " + std::to_string(node.skin) +
                             " does not exist");
        const tinygltf::Primitive& source = model.meshes[size_t(mesh)].primitives[size_t(primitive.meshPrimitive)];
        const bool skinned = node.skin >= 0 && source.attributes.count("JOINTS_0") != 0;
        rigged.skin = skinned ? node.skin : -1;

        // What the loader put between the node and the primitive (none today; an instance
        // transform where a file has them).
        const glm::mat4& nodeToModel = modelFromNode[size_t(primitive.node)];
        if (std::abs(glm::determinant(nodeToModel)) > 1e-30f) {
            const glm::mat4 nodeFromMesh = glm::inverse(nodeToModel) * primitive.modelFromMesh;
            bool identity = true;
            for (int c = 0; c < 4; ++c)
                for (int r = 0; r < 4; ++r)
                    identity = identity && std::abs(nodeFromMesh[c][r] - (c == r ? 1.0f : 0.0f)) < 1e-4f;
            if (!identity && std::isfinite(glm::determinant(nodeFromMesh)))
                rigged.nodeFromMesh = nodeFromMesh;
        }
        rigged.meshBoundsMin = glm::vec3(std::numeric_limits<float>::max());
        rigged.meshBoundsMax = glm::vec3(std::numeric_limits<float>::lowest());
        for (const glm::vec3& p : primitive.positions) {
            rigged.meshBoundsMin = glm::min(rigged.meshBoundsMin, p);
            rigged.meshBoundsMax = glm::max(rigged.meshBoundsMax, p);
        }
        const auto key = std::make_tuple(mesh, primitive.meshPrimitive, rigged.skin);
        auto found = shared.find(key);
        if (found == shared.end()) {
            const std::string what =
                "mesh " + std::to_string(mesh) + " primitive " + std::to_string(primitive.meshPrimitive);
            found =
                shared
                    .emplace(key, readDeformation(model, primitive, source,
                                                  skinned ? &rig.skins[size_t(node.skin)] : nullptr, morphFloats, what))
                    .first;
        }
        rigged.deformation = found->second;
        if (rigged.deformation && rigged.deformation->influences.empty())
            rigged.skin = -1; // morphed, not skinned
    }
}

Interpolation interpolationOf(const std::string& name, const std::string& what)
{
    if (name.empty() || name == "LINEAR")
        return Interpolation::Linear;
    if (name == "STEP")
        return Interpolation::Step;
    if (name == "CUBICSPLINE")
        return Interpolation::CubicSpline;
    throw InputError(what + ": interpolation '" + name + "' is not LINEAR, STEP or CUBICSPLINE");
}

AnimationSampler readSampler(const tinygltf::Model& model, const tinygltf::AnimationSampler& source,
                             AnimatedProperty property, int components, size_t& keyframeFloats, const std::string& what)
{
    AnimationSampler sampler;
    sampler.interpolation = interpolationOf(source.interpolation, what);
    sampler.components = components;
    sampler.times = readChecked(model, source.input, 1, what + " input", "float", isFloat);
    if (sampler.times.empty())
        throw InputError(what + ": input has no keyframes");
    for (size_t k = 1; k < sampler.times.size(); ++k)
        if (!(sampler.times[k] > sampler.times[k - 1]))
            throw InputError(what + ": keyframe times do not increase (keyframe " + str(k - 1) + " at " +
                             std::to_string(sampler.times[k - 1]) + " s, keyframe " + str(k) + " at " +
                             std::to_string(sampler.times[k]) + " s)");
    const bool quantisable = property == AnimatedProperty::Rotation || property == AnimatedProperty::Weights;
    const int elementComponents = property == AnimatedProperty::Weights ? 1 : components;
    sampler.values =
        readChecked(model, source.output, elementComponents, what + " output",
                    quantisable ? "float or normalized integer" : "float",
                    [&](const tinygltf::Accessor& a) { return isFloat(a) || (quantisable && isNormalizedInteger(a)); });
    const size_t perKeyframe = size_t(components) * (sampler.interpolation == Interpolation::CubicSpline ? 3 : 1);
    if (sampler.values.size() != sampler.times.size() * perKeyframe)
        throw InputError(what + ": " + str(sampler.times.size()) + " keyframe times but " +
                         str(sampler.values.size() / size_t(elementComponents)) + " output elements (" +
                         str(sampler.times.size() * perKeyframe / size_t(elementComponents)) + " expected)");
    keyframeFloats += sampler.times.size() + sampler.values.size();
    if (keyframeFloats > kMaxKeyframeFloats)
        throw InputError("the animations hold more than " + str(kMaxKeyframeFloats) + " keyframe numbers");
    return sampler;
}

void readAnimations(const tinygltf::Model& model, GltfRig& rig)
{
    size_t keyframeFloats = 0;
    for (size_t a = 0; a < model.animations.size(); ++a) {
        const tinygltf::Animation& source = model.animations[a];
        const std::string what = "animation " + str(a);
        Animation animation;
        animation.name = source.name;
        animation.samplers.resize(source.samplers.size());
        std::vector<bool> read(source.samplers.size(), false);
        for (size_t c = 0; c < source.channels.size(); ++c) {
            const tinygltf::AnimationChannel& channel = source.channels[c];
            const std::string channelWhat = what + " channel " + str(c);
            AnimationChannel out;
            if (channel.target_path == "translation")
                out.property = AnimatedProperty::Translation;
            else if (channel.target_path == "rotation")
                out.property = AnimatedProperty::Rotation;
            else if (channel.target_path == "scale")
                out.property = AnimatedProperty::Scale;
            else if (channel.target_path == "weights")
                out.property = AnimatedProperty::Weights;
            else {
                LUMAR_LOG(Render, Warn) << channelWhat << " animates '" << channel.target_path << "', ignored";
                continue;
            }
            if (channel.target_node == -1)
                continue; // glTF 2.0 §3.11: a channel without a node is ignored (an extension's)
            if (channel.target_node < 0 || size_t(channel.target_node) >= model.nodes.size())
                throw InputError(channelWhat + " targets node " + std::to_string(channel.target_node) +
                                 ", which does not exist (the file has " + str(model.nodes.size()) + ")");
            out.node = channel.target_node;
            const RigNode& node = rig.nodes[size_t(out.node)];
            if (node.matrix)
                throw InputError(channelWhat + " targets node " + std::to_string(out.node) +
                                 ", which has a matrix (only translation, rotation and scale can be animated)");
            int components = out.property == AnimatedProperty::Rotation ? 4 : 3;
            if (out.property == AnimatedProperty::Weights) {
                components = int(node.weights.size());
                if (components == 0)
                    throw InputError(channelWhat + " animates the morph weights of node " + std::to_string(out.node) +
                                     ", which has no mesh with morph targets");
            }
            if (channel.sampler < 0 || size_t(channel.sampler) >= source.samplers.size())
                throw InputError(channelWhat + ": sampler " + std::to_string(channel.sampler) + " does not exist");
            out.sampler = channel.sampler;
            const size_t s = size_t(channel.sampler);
            if (!read[s]) {
                animation.samplers[s] = readSampler(model, source.samplers[s], out.property, components, keyframeFloats,
                                                    what + " sampler " + str(s));
                read[s] = true;
                animation.duration = std::max(animation.duration, animation.samplers[s].times.back());
            } else if (animation.samplers[s].components != components) {
                throw InputError(channelWhat + ": sampler " + str(s) + " has " +
                                 str(size_t(animation.samplers[s].components)) + " components per keyframe, " +
                                 channel.target_path + " of node " + std::to_string(out.node) + " needs " +
                                 std::to_string(components));
            }
            animation.channels.push_back(out);
        }
        rig.animations.push_back(std::move(animation));
    }
}

} // namespace

bool hasRig(const tinygltf::Model& model)
{
    if (!model.animations.empty())
        return true;
    for (const tinygltf::Node& node : model.nodes)
        if (node.skin >= 0 && node.mesh >= 0)
            return true;
    for (const tinygltf::Mesh& mesh : model.meshes)
        for (const tinygltf::Primitive& primitive : mesh.primitives)
            if (!primitive.targets.empty())
                return true;
    return false;
}

std::shared_ptr<GltfRig> readGltfRig(const tinygltf::Model& model, const std::vector<GltfPrimitive>& primitives)
{
    auto rig = std::make_shared<GltfRig>();
    readHierarchy(model, *rig);
    const std::vector<size_t> targetCounts = meshTargetCounts(model);
    readRestWeights(model, targetCounts, *rig);
    readSkins(model, *rig);
    readPrimitives(model, primitives, *rig);
    readAnimations(model, *rig);
    return rig;
}

} // namespace lumar::gltf
