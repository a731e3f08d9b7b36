#include "gles_renderer/assets/gltf_model.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <optional>
#include <string>
#include <utility>

#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/quaternion.hpp>

#include "core/error.h"
#include "core/log.h"
#include "gles_renderer/assets/gltf_accessors.h"
#include "gles_renderer/assets/gltf_materials.h"
#include "gles_renderer/assets/gltf_parse.h"
#include "gles_renderer/assets/gltf_rig_reader.h"
#include "gles_renderer/assets/model_pose.h"
#include "gles_renderer/assets/tangent_space.h"

namespace lumar {
namespace {

// Extensions a file may require that this loader honours. Any other required extension
// (Draco, meshopt, basisu, texture transforms...) would make us draw the model wrongly.
// The whole scene, all instances counted: about 38 times the heaviest model we test with
// (ToyCar, 109k triangles), and some 300 MB of vertex data at most.
constexpr size_t kMaxModelTriangles = size_t(1) << 22;
constexpr size_t kMaxModelVertices = size_t(1) << 22;

const char* const kSupportedRequiredExtensions[] = {"KHR_materials_emissive_strength", "LUMAR_materials_lafortune"};
// Honoured since issue 20 (kept apart so the list above merges cleanly).
const char* const kSupportedRequiredExtensionsStatic[] = {"KHR_texture_transform", "KHR_mesh_quantization",
                                                          "KHR_materials_unlit", "EXT_mesh_gpu_instancing",
                                                          "EXT_texture_webp"};
// EXT_mesh_gpu_instancing expands each instance into copies of the node's primitives, each a
// draw call: far more instances than a kiosk model has, few enough draw calls to stay cheap.
constexpr size_t kMaxInstancesPerNode = 4096;

template <typename Vec> std::vector<Vec> toVectors(const std::vector<float>& flat)
{
    constexpr size_t n = sizeof(Vec) / sizeof(float);
    std::vector<Vec> out(flat.size() / n);
    for (size_t i = 0; i < out.size(); ++i) {
        for (size_t c = 0; c < n; ++c) {
            out[i][int(c)] = flat[i * n + c];
        }
    }
    return out;
}

// Reads an optional vertex attribute; empty when the primitive does not have it.
// `quantized`: KHR_mesh_quantization's byte/short types too (readQuantizedAccessor); else
// float, or with `allowNormalizedIntegers` normalized unsigned byte/short.
std::vector<float> readAttribute(const tinygltf::Model& model, const tinygltf::Primitive& primitive, const char* name,
                                 int components, bool allowNormalizedIntegers, size_t vertexCount,
                                 bool quantized = false)
{
    const auto found = primitive.attributes.find(name);
    if (found == primitive.attributes.end()) {
        return {};
    }
    std::vector<float> values;
    try {
        values = quantized ? gltf::readQuantizedAccessor(model, found->second, components)
                           : gltf::readFloatAccessor(model, found->second, components, allowNormalizedIntegers);
    } catch (const InputError& e) {
        throw InputError(std::string(name) + ": " + e.what());
    }
    if (values.size() != vertexCount * size_t(components)) {
        throw InputError(std::string(name) + " has " + std::to_string(values.size() / size_t(components)) +
                         " elements, POSITION has " + std::to_string(vertexCount));
    }
    return values;
}

// glTF 2.0 §3.7.2.1: strips and fans as triangle lists with the specified winding.
std::vector<uint32_t> toTriangleList(const std::vector<uint32_t>& indices, int mode)
{
    if (mode == TINYGLTF_MODE_TRIANGLES) {
        if (indices.size() % 3 != 0) {
            throw InputError(std::to_string(indices.size()) + " triangle indices is not a multiple of 3");
        }
        return indices;
    }
    std::vector<uint32_t> triangles;
    if (indices.size() < 3) {
        return triangles;
    }
    triangles.reserve((indices.size() - 2) * 3);
    for (size_t i = 0; i + 2 < indices.size(); ++i) {
        if (mode == TINYGLTF_MODE_TRIANGLE_STRIP) {
            const size_t odd = i % 2;
            triangles.insert(triangles.end(), {indices[i], indices[i + 1 + odd], indices[i + 2 - odd]});
        } else { // fan
            triangles.insert(triangles.end(), {indices[i + 1], indices[i + 2], indices[0]});
        }
    }
    return triangles;
}

// The file's normals made unit length, or area-weighted ones where it has none (or, for
// single vertices, a zero-length one).
std::vector<glm::vec3> vertexNormals(const std::vector<float>& fromFile, const std::vector<glm::vec3>& positions,
                                     const std::vector<uint32_t>& indices)
{
    if (fromFile.empty()) {
        return generateVertexNormals(positions, indices);
    }
    std::vector<glm::vec3> normals = toVectors<glm::vec3>(fromFile);
    std::optional<std::vector<glm::vec3>> generated;
    for (size_t i = 0; i < normals.size(); ++i) {
        const float length = glm::length(normals[i]);
        if (length > 1e-20f) {
            normals[i] /= length;
        } else {
            if (!generated) {
                generated = generateVertexNormals(positions, indices);
            }
            normals[i] = (*generated)[i];
        }
    }
    return normals;
}

// The uv set (0 or 1) the primitive's normal map reads: normalTexture.texCoord, or
// KHR_texture_transform's texCoord where it gives one; 0 without a normal map.
int normalMapTexCoord(const tinygltf::Model& model, const tinygltf::Primitive& source)
{
    if (source.material < 0 || size_t(source.material) >= model.materials.size())
        return 0;
    const tinygltf::NormalTextureInfo& normal = model.materials[size_t(source.material)].normalTexture;
    if (normal.index < 0)
        return 0;
    int texCoord = normal.texCoord;
    const auto transform = normal.extensions.find("KHR_texture_transform");
    if (transform != normal.extensions.end() && transform->second.IsObject() && transform->second.Has("texCoord") &&
        transform->second.Get("texCoord").IsInt())
        texCoord = transform->second.Get("texCoord").GetNumberAsInt();
    return texCoord == 1 ? 1 : 0;
}

// The file's tangents (unit xyz, w exactly +-1), or tangents generated from the normal map's
// uvs when it has none or some of its tangents are zero-length.
std::vector<glm::vec4> vertexTangents(const std::vector<float>& fromFile, const GltfPrimitive& primitive,
                                      int normalTexCoord, const std::string& file, const std::string& what)
{
    std::vector<glm::vec4> tangents = toVectors<glm::vec4>(fromFile);
    for (glm::vec4& t : tangents) {
        const float length = glm::length(glm::vec3(t));
        if (!(length > 1e-20f)) {
            LUMAR_LOG(Render, Warn) << file << ": " << what << " has zero-length tangents; generating them all";
            tangents.clear();
            break;
        }
        t = glm::vec4(glm::vec3(t) / length, t.w < 0.0f ? -1.0f : 1.0f);
    }
    if (tangents.empty()) {
        tangents = generateTangents(primitive.positions, primitive.normals,
                                    normalMapUvs(normalTexCoord, primitive.uvs, primitive.uvs1), primitive.indices);
    }
    return tangents;
}

// COLOR_0 (glTF 2.0 §3.7.2.1): VEC3 or VEC4 of float or normalized unsigned byte/short,
// linear; rgb gets alpha 1. Empty when absent.
std::vector<glm::vec4> vertexColors(const tinygltf::Model& model, const tinygltf::Primitive& source, size_t vertexCount)
{
    const auto found = source.attributes.find("COLOR_0");
    if (found == source.attributes.end()) {
        return {};
    }
    const int components = gltf::accessorComponents(model, found->second) == 3 ? 3 : 4;
    const std::vector<float> flat = readAttribute(model, source, "COLOR_0", components, true, vertexCount);
    std::vector<glm::vec4> colors(vertexCount, glm::vec4(1.0f));
    for (size_t i = 0; i < vertexCount; ++i) {
        for (int c = 0; c < components; ++c) {
            colors[i][c] = std::clamp(flat[i * size_t(components) + size_t(c)], 0.0f, 1.0f);
        }
    }
    return colors;
}

// One mesh primitive as lumar data (modelFromMesh left at identity), or nothing when it
// cannot be drawn as triangles.
std::optional<GltfPrimitive> convertPrimitive(const tinygltf::Model& model, const tinygltf::Primitive& source,
                                              const std::string& file, const std::string& what)
{
    const int mode = source.mode < 0 ? TINYGLTF_MODE_TRIANGLES : source.mode;
    if (mode != TINYGLTF_MODE_TRIANGLES && mode != TINYGLTF_MODE_TRIANGLE_STRIP && mode != TINYGLTF_MODE_TRIANGLE_FAN) {
        LUMAR_LOG(Render, Warn) << file << ": " << what << " draws "
                                << (mode == TINYGLTF_MODE_POINTS ? "points" : "lines") << " (mode " << mode
                                << "), skipped: lumar draws only triangles";
        return std::nullopt;
    }
    if (source.attributes.find("POSITION") == source.attributes.end()) {
        LUMAR_LOG(Render, Warn) << file << ": " << what << " has no POSITION, skipped";
        return std::nullopt;
    }
    std::vector<float> positions;
    try {
        positions = gltf::readQuantizedAccessor(model, source.attributes.at("POSITION"), 3);
    } catch (const InputError& e) {
        throw InputError(std::string("POSITION: ") + e.what());
    }
    const size_t vertexCount = positions.size() / 3;

    std::vector<uint32_t> indices;
    if (source.indices != -1) {
        indices = gltf::readIndexAccessor(model, source.indices);
        for (const uint32_t index : indices) {
            if (index >= vertexCount) {
                throw InputError("index " + std::to_string(index) + " is out of range (" + std::to_string(vertexCount) +
                                 " vertices)");
            }
        }
    } else {
        indices.resize(vertexCount);
        for (size_t i = 0; i < vertexCount; ++i) {
            indices[i] = uint32_t(i);
        }
    }
    indices = toTriangleList(indices, mode);
    if (indices.empty()) {
        LUMAR_LOG(Render, Warn) << file << ": " << what << " has no triangles, skipped";
        return std::nullopt;
    }
    if (source.material < -1 || source.material >= int(model.materials.size())) {
        throw InputError("material " + std::to_string(source.material) + " does not exist");
    }

    GltfPrimitive primitive;
    primitive.material = source.material;
    primitive.positions = toVectors<glm::vec3>(positions);
    primitive.indices = std::move(indices);
    primitive.normals = vertexNormals(readAttribute(model, source, "NORMAL", 3, false, vertexCount, true),
                                      primitive.positions, primitive.indices);
    primitive.uvs = toVectors<glm::vec2>(readAttribute(model, source, "TEXCOORD_0", 2, true, vertexCount, true));
    if (primitive.uvs.empty()) {
        primitive.uvs.assign(vertexCount, glm::vec2(0.0f));
    }
    primitive.uvs1 = toVectors<glm::vec2>(readAttribute(model, source, "TEXCOORD_1", 2, true, vertexCount, true));
    primitive.tangents = vertexTangents(readAttribute(model, source, "TANGENT", 4, false, vertexCount, true), primitive,
                                        normalMapTexCoord(model, source), file, what);
    primitive.colors = vertexColors(model, source, vertexCount);
    return primitive;
}

glm::dvec3 vectorOrDefault(const std::vector<double>& values, const glm::dvec3& fallback, const std::string& what)
{
    if (values.empty()) {
        return fallback;
    }
    if (values.size() != 3) {
        throw InputError(what + " must have 3 numbers");
    }
    return {values[0], values[1], values[2]};
}

// The node's local transform: its matrix (column-major) or translation * rotation * scale.
glm::dmat4 localTransform(const tinygltf::Node& node, const std::string& what)
{
    glm::dmat4 local(1.0);
    if (!node.matrix.empty()) {
        if (node.matrix.size() != 16) {
            throw InputError(what + ": matrix must have 16 numbers");
        }
        for (int i = 0; i < 16; ++i) {
            local[i / 4][i % 4] = node.matrix[size_t(i)];
        }
    } else {
        const glm::dvec3 translation = vectorOrDefault(node.translation, glm::dvec3(0.0), what + " translation");
        const glm::dvec3 scale = vectorOrDefault(node.scale, glm::dvec3(1.0), what + " scale");
        glm::dquat rotation(1.0, 0.0, 0.0, 0.0);
        if (!node.rotation.empty()) {
            if (node.rotation.size() != 4) {
                throw InputError(what + ": rotation must have 4 numbers");
            }
            // glTF stores (x, y, z, w); glm's constructor takes w first.
            rotation = glm::dquat(node.rotation[3], node.rotation[0], node.rotation[1], node.rotation[2]);
            const double length = glm::length(rotation);
            if (!(length > 1e-12)) {
                throw InputError(what + ": rotation is not a unit quaternion");
            }
            rotation /= length;
        }
        local = glm::translate(glm::dmat4(1.0), translation) * glm::mat4_cast(rotation) *
                glm::scale(glm::dmat4(1.0), scale);
    }
    for (int c = 0; c < 4; ++c) {
        for (int r = 0; r < 4; ++r) {
            if (!std::isfinite(local[c][r])) {
                throw InputError(what + ": transform holds a non-finite number");
            }
        }
    }
    return local;
}

// The nodes the scene starts from: the default scene's, else scene 0's, else (a file with
// no scenes) every node that is no other node's child.
std::vector<int> sceneRoots(const tinygltf::Model& model)
{
    if (model.defaultScene >= int(model.scenes.size())) {
        throw InputError("default scene " + std::to_string(model.defaultScene) + " does not exist");
    }
    if (!model.scenes.empty()) {
        return model.scenes[size_t(std::max(model.defaultScene, 0))].nodes;
    }
    std::vector<bool> isChild(model.nodes.size(), false);
    for (const tinygltf::Node& node : model.nodes) {
        for (const int child : node.children) {
            if (child >= 0 && size_t(child) < isChild.size()) {
                isChild[size_t(child)] = true;
            }
        }
    }
    std::vector<int> roots;
    for (size_t n = 0; n < model.nodes.size(); ++n) {
        if (!isChild[n]) {
            roots.push_back(int(n));
        }
    }
    return roots;
}

class SceneFlattener {
public:
    SceneFlattener(const tinygltf::Model& model, const std::string& file) : model_(model), file_(file) {}

    // Walks the node trees without recursion (a hostile file could nest nodes deeply enough
    // to overflow the stack) and emits one GltfPrimitive per (node, mesh primitive).
    std::vector<GltfPrimitive> flatten()
    {
        std::vector<GltfPrimitive> out;
        std::vector<bool> visited(model_.nodes.size(), false);
        std::vector<std::pair<int, glm::dmat4>> pending;
        const std::vector<int> roots = sceneRoots(model_);
        for (auto root = roots.rbegin(); root != roots.rend(); ++root) {
            pending.emplace_back(*root, glm::dmat4(1.0));
        }
        while (!pending.empty()) {
            const auto [nodeIndex, modelFromParent] = pending.back();
            pending.pop_back();
            const std::string what = "node " + std::to_string(nodeIndex);
            if (nodeIndex < 0 || size_t(nodeIndex) >= model_.nodes.size()) {
                throw InputError(what + " does not exist");
            }
            // Nodes form disjoint trees (glTF 2.0 §3.5.3); a second visit means a cycle or a
            // shared child, and following it could loop forever.
            if (visited[size_t(nodeIndex)]) {
                throw InputError(what + " is reached twice: the node hierarchy is not a tree");
            }
            visited[size_t(nodeIndex)] = true;
            const tinygltf::Node& node = model_.nodes[size_t(nodeIndex)];
            const glm::dmat4 modelFromNode = modelFromParent * localTransform(node, what);
            for (int c = 0; c < 4; ++c) {
                for (int r = 0; r < 4; ++r) {
                    // Converted to float below: larger magnitudes would become infinities.
                    if (!(std::abs(modelFromNode[c][r]) <= double(std::numeric_limits<float>::max()))) {
                        throw InputError(what + ": the transform takes the model beyond floating-point range");
                    }
                }
            }
            if (node.mesh >= 0 && node.extensions.count("EXT_mesh_gpu_instancing") != 0) {
                for (const glm::dmat4& nodeFromInstance : instanceTransforms(node, what)) {
                    appendMesh(nodeIndex, node.mesh,
                               glm::mat4(checkedFloatRange(modelFromNode * nodeFromInstance, what)), out);
                }
            } else if (node.mesh >= 0) {
                appendMesh(nodeIndex, node.mesh, glm::mat4(modelFromNode), out);
            } else if (node.mesh < -1) {
                throw InputError(what + ": mesh " + std::to_string(node.mesh) + " does not exist");
            }
            for (auto child = node.children.rbegin(); child != node.children.rend(); ++child) {
                pending.emplace_back(*child, modelFromNode);
            }
        }
        return out;
    }

private:
    static glm::dmat4 checkedFloatRange(const glm::dmat4& m, const std::string& what)
    {
        for (int c = 0; c < 4; ++c) {
            for (int r = 0; r < 4; ++r) {
                if (!(std::abs(m[c][r]) <= double(std::numeric_limits<float>::max()))) {
                    throw InputError(what + ": an instance transform takes the model beyond floating-point range");
                }
            }
        }
        return m;
    }

    // EXT_mesh_gpu_instancing: one transform per instance from the TRANSLATION, ROTATION
    // (unit quaternion x, y, z, w) and SCALE accessors, each optional, all of one count.
    std::vector<glm::dmat4> instanceTransforms(const tinygltf::Node& node, const std::string& what) const
    {
        const std::string where = what + " EXT_mesh_gpu_instancing";
        const tinygltf::Value& extension = node.extensions.at("EXT_mesh_gpu_instancing");
        if (!extension.IsObject() || !extension.Has("attributes") || !extension.Get("attributes").IsObject()) {
            throw InputError(where + ": expected an object with \"attributes\"");
        }
        const tinygltf::Value& attributes = extension.Get("attributes");
        const auto read = [&](const char* name, int components) -> std::vector<float> {
            if (!attributes.Has(name)) {
                return {};
            }
            const tinygltf::Value& index = attributes.Get(name);
            if (!index.IsInt()) {
                throw InputError(where + " " + name + ": expected an accessor index");
            }
            try {
                return gltf::readQuantizedAccessor(model_, index.GetNumberAsInt(), components);
            } catch (const InputError& e) {
                throw InputError(where + " " + name + ": " + e.what());
            }
        };
        const std::vector<float> translations = read("TRANSLATION", 3);
        const std::vector<float> rotations = read("ROTATION", 4);
        const std::vector<float> scales = read("SCALE", 3);
        size_t count = 0;
        for (const auto& [values, n] : {std::pair{&translations, 3}, std::pair{&rotations, 4}, std::pair{&scales, 3}}) {
            if (values->empty()) {
                continue;
            }
            const size_t elements = values->size() / size_t(n);
            if (count != 0 && elements != count) {
                throw InputError(where + ": its attributes have different counts (" + std::to_string(count) + " and " +
                                 std::to_string(elements) + ")");
            }
            count = elements;
        }
        if (count > kMaxInstancesPerNode) {
            throw InputError(where + ": " + std::to_string(count) + " instances exceed the limit of " +
                             std::to_string(kMaxInstancesPerNode));
        }
        std::vector<glm::dmat4> transforms(count, glm::dmat4(1.0));
        for (size_t i = 0; i < count; ++i) {
            glm::dmat4& m = transforms[i];
            if (!translations.empty()) {
                m = glm::translate(m,
                                   glm::dvec3(translations[3 * i], translations[3 * i + 1], translations[3 * i + 2]));
            }
            if (!rotations.empty()) {
                glm::dquat q(rotations[4 * i + 3], rotations[4 * i], rotations[4 * i + 1], rotations[4 * i + 2]);
                const double length = glm::length(q);
                if (!(length > 1e-12)) {
                    throw InputError(where + " ROTATION " + std::to_string(i) + " is not a unit quaternion");
                }
                m = m * glm::mat4_cast(q / length);
            }
            if (!scales.empty()) {
                m = glm::scale(m, glm::dvec3(scales[3 * i], scales[3 * i + 1], scales[3 * i + 2]));
            }
        }
        return transforms;
    }

    void appendMesh(int nodeIndex, int meshIndex, const glm::mat4& modelFromMesh, std::vector<GltfPrimitive>& out)
    {
        if (size_t(meshIndex) >= model_.meshes.size()) {
            throw InputError("mesh " + std::to_string(meshIndex) + " does not exist");
        }
        const tinygltf::Mesh& mesh = model_.meshes[size_t(meshIndex)];
        for (size_t p = 0; p < mesh.primitives.size(); ++p) {
            const auto key = std::make_pair(meshIndex, p);
            auto cached = converted_.find(key);
            if (cached == converted_.end()) {
                const std::string what = "mesh " + std::to_string(meshIndex) + " primitive " + std::to_string(p);
                try {
                    cached = converted_.emplace(key, convertPrimitive(model_, mesh.primitives[p], file_, what)).first;
                } catch (const InputError& e) {
                    throw InputError(what + ": " + e.what());
                }
            }
            if (cached->second) {
                // Instances are copies: a few nodes naming one large mesh must not multiply it
                // past what any scene of ours draws (issue 16).
                triangles_ += cached->second->indices.size() / 3;
                vertices_ += cached->second->positions.size();
                if (triangles_ > kMaxModelTriangles || vertices_ > kMaxModelVertices) {
                    throw InputError("the scene's mesh instances hold more than " + std::to_string(kMaxModelTriangles) +
                                     " triangles or " + std::to_string(kMaxModelVertices) + " vertices");
                }
                out.push_back(*cached->second);
                out.back().modelFromMesh = modelFromMesh;
                out.back().node = nodeIndex;
                out.back().meshPrimitive = int(p);
            }
        }
    }

    const tinygltf::Model& model_;
    const std::string& file_;
    size_t triangles_ = 0; // over all instances so far
    size_t vertices_ = 0;
    // Instanced meshes are decoded once and copied per instance.
    std::map<std::pair<int, size_t>, std::optional<GltfPrimitive>> converted_;
};

void checkRequiredExtensions(const tinygltf::Model& model)
{
    for (const std::string& extension : model.extensionsRequired) {
        if (std::find(std::begin(kSupportedRequiredExtensions), std::end(kSupportedRequiredExtensions), extension) ==
                std::end(kSupportedRequiredExtensions) &&
            std::find(std::begin(kSupportedRequiredExtensionsStatic), std::end(kSupportedRequiredExtensionsStatic),
                      extension) == std::end(kSupportedRequiredExtensionsStatic)) {
            throw InputError("requires extension " + extension + ", which lumar does not support");
        }
    }
}

// Skins and morph targets applied in the rest pose; the rig kept where animations move it
// (a model without animations costs nothing per frame).
void poseRestAndKeepRig(const tinygltf::Model& source, GltfModel& model)
{
    if (!gltf::hasRig(source)) {
        return;
    }
    std::shared_ptr<GltfRig> rig = gltf::readGltfRig(source, model.primitives);
    const ModelPoser rest(rig);
    applyPose(rest, model.primitives);
    if (!rig->animations.empty()) {
        model.rig = std::move(rig);
    }
}

std::string oneLine(std::string text)
{
    std::replace_if(
        text.begin(), text.end(), [](char c) { return c == '\n' || c == '\r'; }, ' ');
    return text;
}

} // namespace

std::array<glm::vec3, 2> GltfUvTransform::rows() const
{
    // KHR_texture_transform: translation * rotation * scale, the rotation matrix as the
    // extension writes it ((cos, sin), (-sin, cos) by rows).
    const float c = std::cos(rotation), s = std::sin(rotation);
    return {glm::vec3(c * scale.x, s * scale.y, offset.x), glm::vec3(-s * scale.x, c * scale.y, offset.y)};
}

size_t GltfModel::triangleCount() const
{
    size_t triangles = 0;
    for (const GltfPrimitive& primitive : primitives) {
        triangles += primitive.indices.size() / 3;
    }
    return triangles;
}

float volumeThickness(const GltfTransmission& transmission, const std::vector<GltfTexture>& textures)
{
    const int index = transmission.thicknessTexture;
    if (index < 0 || size_t(index) >= textures.size())
        return transmission.thickness;
    const Image8& image = textures[size_t(index)].image;
    const size_t texels = size_t(image.width) * size_t(image.height);
    if (texels == 0 || image.channels < 2 || image.data.size() < texels * size_t(image.channels))
        return transmission.thickness;
    double sum = 0.0;
    for (size_t i = 0; i < texels; ++i)
        sum += image.data[i * size_t(image.channels) + 1];
    return float(double(transmission.thickness) * sum / (255.0 * double(texels)));
}

GltfModel loadGltfModel(const std::filesystem::path& file)
{
    const std::string fileName = file.string();
    try {
        const tinygltf::Model source = gltf::parseGltfFile(file);
        checkRequiredExtensions(source);

        GltfModel model;
        model.file = file;
        gltf::ConvertedMaterials materials = gltf::convertMaterials(source, fileName);
        model.materials = std::move(materials.materials);
        model.textures = std::move(materials.textures);
        model.textureSamplers = std::move(materials.samplers);
        model.primitives = SceneFlattener(source, fileName).flatten();
        if (model.primitives.empty()) {
            throw InputError("the scene holds no triangles");
        }
        poseRestAndKeepRig(source, model);

        glm::vec3 lo(std::numeric_limits<float>::max());
        glm::vec3 hi(std::numeric_limits<float>::lowest());
        for (const GltfPrimitive& primitive : model.primitives) {
            for (const glm::vec3& p : primitive.positions) {
                const glm::vec3 world = glm::vec3(primitive.modelFromMesh * glm::vec4(p, 1.0f));
                lo = glm::min(lo, world);
                hi = glm::max(hi, world);
            }
        }
        if (!std::isfinite(lo.x + lo.y + lo.z + hi.x + hi.y + hi.z)) {
            throw InputError("the node transforms take the model beyond floating-point range");
        }
        model.boundsMin = lo;
        model.boundsMax = hi;
        return model;
    } catch (const InputError& e) {
        throw InputError(oneLine(fileName + ": " + e.what()));
    }
}

} // namespace lumar
