#include "gles_renderer/assets/mesh_simplify.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <unordered_map>

#include "core/error.h"

namespace lumar {
namespace {

struct CellKey {
    int32_t x, y, z;
    bool operator==(const CellKey&) const = default;
};

struct CellKeyHash {
    size_t operator()(const CellKey& k) const
    {
        return size_t(k.x) * 73856093u ^ size_t(k.y) * 19349663u ^ size_t(k.z) * 83492791u;
    }
};

struct CellSum {
    glm::vec3 position{0.0f}, normal{0.0f};
    glm::vec2 uv{0.0f};
    glm::vec3 tangent{0.0f};
    float handedness = 0.0f;
    int count = 0;
};

glm::vec3 normalisedOr(const glm::vec3& v, const glm::vec3& fallback)
{
    const float length = glm::length(v);
    return length > 1e-12f ? v / length : fallback;
}

} // namespace

GltfPrimitive simplifyByClustering(const GltfPrimitive& primitive, float cellSize)
{
    if (!(cellSize > 0.0f) || !std::isfinite(cellSize))
        throw InputError("vertex clustering needs a positive cell size");
    const size_t n = primitive.positions.size();
    std::unordered_map<CellKey, uint32_t, CellKeyHash> cellOf;
    std::vector<CellSum> cells;
    std::vector<uint32_t> remap(n);
    for (size_t i = 0; i < n; ++i) {
        const glm::vec3 q = glm::floor(primitive.positions[i] / cellSize);
        const CellKey key{int32_t(q.x), int32_t(q.y), int32_t(q.z)};
        const auto [it, inserted] = cellOf.try_emplace(key, uint32_t(cells.size()));
        if (inserted)
            cells.emplace_back();
        CellSum& c = cells[it->second];
        c.position += primitive.positions[i];
        c.normal += primitive.normals[i];
        c.uv += primitive.uvs[i];
        c.tangent += glm::vec3(primitive.tangents[i]);
        c.handedness += primitive.tangents[i].w;
        ++c.count;
        remap[i] = it->second;
    }

    GltfPrimitive out;
    out.modelFromMesh = primitive.modelFromMesh;
    out.material = primitive.material;
    out.positions.reserve(cells.size());
    for (const CellSum& c : cells) {
        const float inv = 1.0f / float(c.count);
        const glm::vec3 normal = normalisedOr(c.normal, glm::vec3(0, 0, 1));
        out.positions.push_back(c.position * inv);
        out.normals.push_back(normal);
        out.uvs.push_back(c.uv * inv);
        // The tangent kept perpendicular to the averaged normal.
        const glm::vec3 t = c.tangent - normal * glm::dot(normal, c.tangent);
        out.tangents.emplace_back(normalisedOr(t, glm::vec3(0.0f)), c.handedness < 0.0f ? -1.0f : 1.0f);
    }
    for (size_t t = 0; t + 2 < primitive.indices.size(); t += 3) {
        const uint32_t a = remap[primitive.indices[t]], b = remap[primitive.indices[t + 1]],
                       c = remap[primitive.indices[t + 2]];
        if (a != b && b != c && a != c)
            out.indices.insert(out.indices.end(), {a, b, c});
    }
    return out;
}

GltfModel makeProxyModel(const GltfModel& model, int cellsAlongLongestSide)
{
    if (cellsAlongLongestSide < 1)
        throw InputError("a proxy needs at least one cell along the model");
    const glm::vec3 extent = model.boundsMax - model.boundsMin;
    const float longest = std::max({extent.x, extent.y, extent.z});
    GltfModel proxy;
    proxy.file = model.file;
    proxy.materials = model.materials;
    proxy.textures = model.textures;
    proxy.boundsMin = model.boundsMin;
    proxy.boundsMax = model.boundsMax;
    for (const GltfPrimitive& p : model.primitives) {
        // The grid step in model space, expressed in this primitive's mesh space.
        const glm::mat3 linear(p.modelFromMesh);
        const float scale = std::max({glm::length(linear[0]), glm::length(linear[1]), glm::length(linear[2])});
        const float cell = longest > 0.0f && scale > 0.0f ? longest / float(cellsAlongLongestSide) / scale : 0.0f;
        proxy.primitives.push_back(cell > 0.0f ? simplifyByClustering(p, cell) : p);
    }
    return proxy;
}

} // namespace lumar
