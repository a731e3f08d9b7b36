#include "gles_renderer/assets/convex_surface.h"

#include <cmath>
#include <limits>
#include <vector>

#include <glm/glm.hpp>

namespace lumar {

bool isConvexSurface(const GltfModel& model)
{
    std::vector<glm::dvec3> corners; // three a triangle, counter-clockwise from outside
    for (const GltfPrimitive& primitive : model.primitives) {
        if (primitive.indices.size() % 3 != 0 ||
            corners.size() + primitive.indices.size() > 3 * kConvexSurfaceMaxTriangles)
            return false;
        const glm::dmat4 modelFromMesh(primitive.modelFromMesh);
        // A mirroring transform turns the winding (as the renderer's front face does): the
        // second and third corners swap back.
        const bool mirrored = glm::determinant(glm::dmat3(modelFromMesh)) < 0.0;
        for (size_t i = 0; i < primitive.indices.size(); ++i) {
            const size_t corner = mirrored && i % 3 != 0 ? (i % 3 == 1 ? i + 1 : i - 1) : i;
            const uint32_t index = primitive.indices[corner];
            if (index >= primitive.positions.size())
                return false;
            corners.emplace_back(modelFromMesh * glm::dvec4(glm::dvec3(primitive.positions[index]), 1.0));
        }
    }
    if (corners.empty())
        return false;
    glm::dvec3 low(std::numeric_limits<double>::infinity());
    glm::dvec3 high(-std::numeric_limits<double>::infinity());
    for (const glm::dvec3& p : corners) {
        low = glm::min(low, p);
        high = glm::max(high, p);
    }
    const double extent = glm::length(high - low);
    if (!(extent > 0.0) || !std::isfinite(extent))
        return false;
    // Corners on a face's plane up to float rounding of the mesh count as on it.
    const double tolerance = 1e-6 * extent;
    bool anyFace = false;
    for (size_t t = 0; t < corners.size(); t += 3) {
        const glm::dvec3& a = corners[t];
        const glm::dvec3 normal = glm::cross(corners[t + 1] - a, corners[t + 2] - a);
        const double length = glm::length(normal);
        if (!(length > 1e-12 * extent * extent))
            continue; // degenerate: covers no pixel
        anyFace = true;
        for (const glm::dvec3& p : corners)
            if (glm::dot(normal, p - a) > tolerance * length)
                return false;
    }
    return anyFace;
}

} // namespace lumar
