#include "object_placement.h"

#include <algorithm>

#include <glm/gtc/matrix_transform.hpp>

namespace lumar {

glm::dmat4 markerFromModel(const ObjectConfig& object, const glm::vec3& boundsMin, const glm::vec3& boundsMax)
{
    const glm::dvec3 lo(boundsMin), hi(boundsMax);
    const glm::dvec3 extent = hi - lo;
    const double longest = std::max({extent.x, extent.y, extent.z});
    const double scale = (object.size > 0.0 && longest > 0.0) ? object.size / longest : object.scale;
    // The point of the model that lands on the marker's origin: bottom centre of the box.
    const glm::dvec3 anchor(0.5 * (lo.x + hi.x), lo.y, 0.5 * (lo.z + hi.z));

    glm::dmat4 m(1.0);
    m = glm::translate(m, object.offset);
    m = glm::rotate(m, glm::radians(object.rotationDeg.z), glm::dvec3(0, 0, 1));
    m = glm::rotate(m, glm::radians(object.rotationDeg.y), glm::dvec3(0, 1, 0));
    m = glm::rotate(m, glm::radians(object.rotationDeg.x), glm::dvec3(1, 0, 0));
    m = glm::rotate(m, glm::radians(90.0), glm::dvec3(1, 0, 0)); // model +Y -> marker +Z
    m = glm::scale(m, glm::dvec3(scale));
    m = glm::translate(m, -anchor);
    return m;
}

glm::dmat3 environmentFromMarker()
{
    // Marker (x, y, z) with z up -> environment (x, z, -y) with y up: a -90 degree turn about x.
    return glm::dmat3(glm::rotate(glm::dmat4(1.0), glm::radians(-90.0), glm::dvec3(1, 0, 0)));
}

} // namespace lumar
