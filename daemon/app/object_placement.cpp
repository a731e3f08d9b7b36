#include "object_placement.h"

#include <algorithm>
#include <cmath>

#include <glm/gtc/matrix_transform.hpp>

namespace lumar {

glm::dmat4 markerFromModel(const ObjectConfig& object, const glm::vec3& boundsMin, const glm::vec3& boundsMax)
{
    const glm::dvec3 lo(boundsMin), hi(boundsMax);
    const glm::dvec3 extent = hi - lo;
    const double longest = std::max({extent.x, extent.y, extent.z});
    const double scale = (object.size > 0.0 && longest > 0.0) ? object.size / longest : object.scale;
    const glm::dvec3 centre = 0.5 * (lo + hi);

    // The model centred, scaled, upright (+Y -> +Z), then turned by `rotation` (Rz·Ry·Rx).
    glm::dmat4 turned(1.0);
    turned = glm::rotate(turned, glm::radians(object.rotationDeg.z), glm::dvec3(0, 0, 1));
    turned = glm::rotate(turned, glm::radians(object.rotationDeg.y), glm::dvec3(0, 1, 0));
    turned = glm::rotate(turned, glm::radians(object.rotationDeg.x), glm::dvec3(1, 0, 0));
    turned = glm::rotate(turned, glm::radians(90.0), glm::dvec3(1, 0, 0)); // model +Y -> marker +Z
    turned = glm::scale(turned, glm::dvec3(scale));
    // The box, centred on the origin, stays centred when turned; its lowest corner is
    // sum_j |z row of column j| * half extent j below the centre: lift it onto z = 0.
    double lift = 0.0;
    for (int j = 0; j < 3; ++j)
        lift += std::abs(turned[j][2]) * 0.5 * extent[j];

    glm::dmat4 m(1.0);
    m = glm::translate(m, object.offset);
    m = glm::rotate(m, glm::radians(object.headingDeg), glm::dvec3(0, 0, 1));
    m = glm::translate(m, glm::dvec3(0.0, 0.0, lift));
    m = m * turned;
    m = glm::translate(m, -centre);
    return m;
}

} // namespace lumar
