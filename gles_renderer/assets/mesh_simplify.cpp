#include "gles_renderer/assets/mesh_simplify.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>

#include <meshoptimizer.h>

#include "core/error.h"

namespace lumar {
namespace {

static_assert(sizeof(glm::vec3) == 3 * sizeof(float), "meshoptimizer reads positions as packed float triples");

// meshopt_simplify's error is a quadric error, a weighted mean of squared distances from the
// planes of the triangles a vertex has absorbed: a single original vertex may end up
// further from the stand-in than the bound. A level's bound is therefore this share of its
// cell. Measured on the shipped models (lumar_roadster, CesiumMilkTruck, a 48x24 sphere) at
// 48 to 8 cells: no original vertex further than 0.6 cell from the stand-in (sampled), and
// in tests/gl's cube faces the size-chosen levels 6 % above the finest (6.5 vs 6.1 % image
// error; vertex clustering: 15.0 vs 14.8 %). A share of 0.25 gave 10 % above, 0.5 gave 14 %.
constexpr float kErrorShareOfCell = 0.2f;

void checkPrimitive(const GltfPrimitive& p)
{
    const size_t n = p.positions.size();
    if (p.normals.size() != n || p.uvs.size() != n || p.tangents.size() != n)
        throw InputError("mesh simplification: " + std::to_string(n) + " positions but " +
                         std::to_string(p.normals.size()) + " normals, " + std::to_string(p.uvs.size()) + " uvs, " +
                         std::to_string(p.tangents.size()) + " tangents");
    if (p.indices.size() % 3 != 0)
        throw InputError("mesh simplification: " + std::to_string(p.indices.size()) +
                         " indices is not a whole number of triangles");
    for (const uint32_t i : p.indices)
        if (i >= n)
            throw InputError("mesh simplification: index " + std::to_string(i) + " beyond " + std::to_string(n) +
                             " vertices");
}

template <typename T>
std::vector<T> remapped(const std::vector<T>& stream, const std::vector<uint32_t>& remap, size_t kept)
{
    std::vector<T> out(kept);
    meshopt_remapVertexBuffer(out.data(), stream.data(), stream.size(), sizeof(T), remap.data());
    return out;
}

} // namespace

GltfPrimitive simplifyPrimitive(const GltfPrimitive& primitive, float maxError)
{
    if (!(maxError > 0.0f) || !std::isfinite(maxError))
        throw InputError("mesh simplification needs a positive error bound");
    checkPrimitive(primitive);
    const size_t n = primitive.positions.size();
    // meshopt_simplify takes the error relative to the mesh's extent.
    const float extent = n > 0 ? meshopt_simplifyScale(&primitive.positions[0].x, n, sizeof(glm::vec3)) : 0.0f;
    if (!(extent > 0.0f) || primitive.indices.empty())
        return primitive;

    // Target count 0: the error bound alone decides where the collapses stop. The vertices
    // stay indexed as they are, so meshopt sees uv and normal seams and keeps them closed.
    std::vector<uint32_t> indices(primitive.indices.size());
    indices.resize(meshopt_simplify(indices.data(), primitive.indices.data(), primitive.indices.size(),
                                    &primitive.positions[0].x, n, sizeof(glm::vec3), 0, maxError / extent, 0, nullptr));

    // Only the vertices the remaining triangles use, in the order they first appear.
    std::vector<uint32_t> remap(n);
    const size_t kept = meshopt_optimizeVertexFetchRemap(remap.data(), indices.data(), indices.size(), n);
    GltfPrimitive out;
    out.modelFromMesh = primitive.modelFromMesh;
    out.material = primitive.material;
    out.indices.resize(indices.size());
    meshopt_remapIndexBuffer(out.indices.data(), indices.data(), indices.size(), remap.data());
    out.positions = remapped(primitive.positions, remap, kept);
    out.normals = remapped(primitive.normals, remap, kept);
    out.uvs = remapped(primitive.uvs, remap, kept);
    out.tangents = remapped(primitive.tangents, remap, kept);
    if (primitive.uvs1.size() == n)
        out.uvs1 = remapped(primitive.uvs1, remap, kept);
    if (primitive.colors.size() == n)
        out.colors = remapped(primitive.colors, remap, kept);
    return out;
}

std::vector<GltfPrimitive> makeProxyPrimitives(const GltfModel& model, int cellsAlongLongestSide)
{
    if (cellsAlongLongestSide < 1)
        throw InputError("a proxy needs at least one cell along the model");
    const glm::vec3 extent = model.boundsMax - model.boundsMin;
    const float longest = std::max({extent.x, extent.y, extent.z});
    std::vector<GltfPrimitive> primitives;
    primitives.reserve(model.primitives.size());
    for (const GltfPrimitive& p : model.primitives) {
        // The error bound in model space, expressed in this primitive's mesh space.
        const glm::mat3 linear(p.modelFromMesh);
        const float scale = std::max({glm::length(linear[0]), glm::length(linear[1]), glm::length(linear[2])});
        const float cell = longest / float(cellsAlongLongestSide);
        const float error = longest > 0.0f && scale > 0.0f ? kErrorShareOfCell * cell / scale : 0.0f;
        primitives.push_back(error > 0.0f ? simplifyPrimitive(p, error) : p);
    }
    return primitives;
}

GltfModel makeProxyModel(const GltfModel& model, int cellsAlongLongestSide)
{
    GltfModel proxy;
    proxy.primitives = makeProxyPrimitives(model, cellsAlongLongestSide);
    proxy.file = model.file;
    proxy.materials = model.materials;
    proxy.textures = model.textures;
    proxy.textureSamplers = model.textureSamplers;
    proxy.boundsMin = model.boundsMin;
    proxy.boundsMax = model.boundsMax;
    return proxy;
}

} // namespace lumar
