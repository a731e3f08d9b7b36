// Where a frame's rays may point: the convex cone spanned by its four corner rays, given by
// the inward unit normals of its four sides. The fake camera tests its lazily baked tiles
// (environment cube, lit table) against it to bake only those a frame may read.
#pragma once

#include <array>

#include <glm/glm.hpp>

namespace lumar {

struct ViewCone {
    std::array<glm::vec3, 4> inward{};

    // The cone spanned by `corners`, four directions in order around it (either winding),
    // spanning less than a half-space.
    static ViewCone spannedBy(const std::array<glm::vec3, 4>& corners)
    {
        glm::vec3 inside(0.0f);
        for (const glm::vec3& c : corners) {
            inside += glm::normalize(c);
        }
        ViewCone view;
        for (size_t k = 0; k < 4; ++k) {
            const glm::vec3 n = glm::normalize(glm::cross(corners[k], corners[(k + 1) % 4]));
            view.inward[k] = glm::dot(n, inside) < 0.0f ? -n : n;
        }
        return view;
    }
};

} // namespace lumar
