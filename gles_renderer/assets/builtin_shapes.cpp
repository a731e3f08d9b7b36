#include "gles_renderer/assets/builtin_shapes.h"

#include <array>
#include <cmath>
#include <numbers>
#include <string>

#include "core/error.h"

namespace lumar {
namespace {

GltfModel withDefaultMaterial(GltfPrimitive primitive, const char* name)
{
    GltfModel model;
    model.file = std::string("builtin:") + name;
    GltfMaterial material;
    material.name = name;
    material.baseColorFactor = glm::vec4(0.8f, 0.8f, 0.8f, 1.0f);
    material.metallicFactor = 0.0f;
    material.roughnessFactor = 0.5f;
    model.materials.push_back(material);
    primitive.material = 0;
    model.boundsMin = glm::vec3(-0.5f);
    model.boundsMax = glm::vec3(0.5f);
    model.primitives.push_back(std::move(primitive));
    return model;
}

} // namespace

bool isBuiltinShape(std::string_view name)
{
    return name == "sphere" || name == "cube";
}

GltfModel makeBuiltinShape(std::string_view name)
{
    if (name == "sphere")
        return makeUvSphere(64, 32);
    if (name == "cube")
        return makeCube();
    throw InputError("'" + std::string(name) + "' is not a built-in shape (sphere, cube)");
}

GltfModel makeUvSphere(int segments, int rings)
{
    if (segments < 3 || rings < 2 || segments > 1024 || rings > 1024)
        throw InputError("a UV sphere needs 3..1024 segments and 2..1024 rings");
    constexpr float kPi = std::numbers::pi_v<float>;
    GltfPrimitive p;
    for (int r = 0; r <= rings; ++r) {
        const float theta = kPi * float(r) / float(rings); // from +Y
        for (int s = 0; s <= segments; ++s) {
            const float phi = 2.0f * kPi * float(s) / float(segments);
            const glm::vec3 n(std::sin(theta) * std::cos(phi), std::cos(theta), -std::sin(theta) * std::sin(phi));
            p.positions.push_back(0.5f * n);
            p.normals.push_back(n);
            p.uvs.emplace_back(float(s) / float(segments), float(r) / float(rings));
            // d(position)/du: along increasing phi, the direction u grows.
            p.tangents.emplace_back(-std::sin(phi), 0.0f, -std::cos(phi), 1.0f);
        }
    }
    const auto index = [&](int r, int s) { return uint32_t(r * (segments + 1) + s); };
    for (int r = 0; r < rings; ++r)
        for (int s = 0; s < segments; ++s) {
            // Counter-clockwise seen from outside (glTF front faces).
            const uint32_t a = index(r, s), b = index(r + 1, s), c = index(r + 1, s + 1), d = index(r, s + 1);
            if (r != 0)
                p.indices.insert(p.indices.end(), {a, b, d});
            if (r != rings - 1)
                p.indices.insert(p.indices.end(), {d, b, c});
        }
    return withDefaultMaterial(std::move(p), "sphere");
}

GltfModel makeCube()
{
    GltfPrimitive p;
    // Each face: normal, and the tangent (u direction); bitangent = normal x tangent.
    const std::array<std::pair<glm::vec3, glm::vec3>, 6> faces{{
        {{1, 0, 0}, {0, 0, -1}},
        {{-1, 0, 0}, {0, 0, 1}},
        {{0, 1, 0}, {1, 0, 0}},
        {{0, -1, 0}, {1, 0, 0}},
        {{0, 0, 1}, {1, 0, 0}},
        {{0, 0, -1}, {-1, 0, 0}},
    }};
    for (const auto& [n, t] : faces) {
        const glm::vec3 b = glm::cross(n, t);
        const uint32_t base = uint32_t(p.positions.size());
        const std::array<glm::vec2, 4> corners{{{-1, -1}, {1, -1}, {1, 1}, {-1, 1}}};
        for (const glm::vec2& c : corners) {
            p.positions.push_back(0.5f * (n + c.x * t + c.y * b));
            p.normals.push_back(n);
            p.uvs.emplace_back(0.5f * (c.x + 1.0f), 0.5f * (1.0f - c.y));
            p.tangents.emplace_back(t, 1.0f);
        }
        p.indices.insert(p.indices.end(), {base, base + 1, base + 2, base, base + 2, base + 3});
    }
    return withDefaultMaterial(std::move(p), "cube");
}

GltfModel makePlane()
{
    GltfPrimitive p;
    // Counter-clockwise seen from +Y: x grows with u, z grows with v. As in makeCube, the
    // bitangent normal x tangent (+Y x +X = -Z) points where v decreases: handedness +1.
    const std::array<glm::vec2, 4> corners{{{-0.5f, -0.5f}, {-0.5f, 0.5f}, {0.5f, 0.5f}, {0.5f, -0.5f}}};
    for (const glm::vec2& c : corners) {
        p.positions.emplace_back(c.x, 0.0f, c.y);
        p.normals.emplace_back(0.0f, 1.0f, 0.0f);
        p.uvs.emplace_back(c.x + 0.5f, c.y + 0.5f);
        p.tangents.emplace_back(1.0f, 0.0f, 0.0f, 1.0f);
    }
    p.indices = {0, 1, 2, 0, 2, 3};
    GltfModel model = withDefaultMaterial(std::move(p), "plane");
    model.materials[0].doubleSided = true;
    model.boundsMin.y = 0.0f;
    model.boundsMax.y = 0.0f;
    return model;
}

GltfModel makeCylinder(int segments)
{
    if (segments < 3 || segments > 1024)
        throw InputError("a cylinder needs 3..1024 segments");
    constexpr float kPi = std::numbers::pi_v<float>;
    GltfPrimitive p;
    // The side: a ring of vertices at each end, the seam duplicated for its uvs; the same
    // parametrisation as makeUvSphere (u along phi, tangent along increasing phi).
    for (int s = 0; s <= segments; ++s) {
        const float phi = 2.0f * kPi * float(s) / float(segments);
        const glm::vec3 n(std::cos(phi), 0.0f, -std::sin(phi));
        for (const float y : {0.5f, -0.5f}) {
            p.positions.emplace_back(0.5f * n.x, y, 0.5f * n.z);
            p.normals.push_back(n);
            p.uvs.emplace_back(float(s) / float(segments), 0.5f - y);
            p.tangents.emplace_back(-std::sin(phi), 0.0f, -std::cos(phi), 1.0f);
        }
    }
    for (int s = 0; s < segments; ++s) {
        const uint32_t top = uint32_t(2 * s), bottom = top + 1, nextTop = top + 2, nextBottom = top + 3;
        // Counter-clockwise seen from outside (glTF front faces).
        p.indices.insert(p.indices.end(), {top, bottom, nextTop, nextTop, bottom, nextBottom});
    }
    // The caps: a fan round a centre vertex each, uvs a disc in the unit square.
    for (const float side : {1.0f, -1.0f}) {
        const uint32_t centre = uint32_t(p.positions.size());
        p.positions.emplace_back(0.0f, 0.5f * side, 0.0f);
        p.normals.emplace_back(0.0f, side, 0.0f);
        p.uvs.emplace_back(0.5f, 0.5f);
        // Bitangent (normal x tangent) x handedness towards decreasing v (-Z), as in makeCube.
        p.tangents.emplace_back(1.0f, 0.0f, 0.0f, side);
        for (int s = 0; s <= segments; ++s) {
            const float phi = 2.0f * kPi * float(s) / float(segments);
            const float x = 0.5f * std::cos(phi), z = -0.5f * std::sin(phi);
            p.positions.emplace_back(x, 0.5f * side, z);
            p.normals.emplace_back(0.0f, side, 0.0f);
            p.uvs.emplace_back(x + 0.5f, z + 0.5f);
            p.tangents.emplace_back(1.0f, 0.0f, 0.0f, side);
        }
        for (int s = 0; s < segments; ++s) {
            const uint32_t a = centre + 1 + uint32_t(s), b = a + 1;
            // Counter-clockwise seen from outside: phi grows counter-clockwise seen from +Y.
            if (side > 0.0f)
                p.indices.insert(p.indices.end(), {centre, a, b});
            else
                p.indices.insert(p.indices.end(), {centre, b, a});
        }
    }
    return withDefaultMaterial(std::move(p), "cylinder");
}

} // namespace lumar
