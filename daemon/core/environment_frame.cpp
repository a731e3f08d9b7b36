#include "core/environment_frame.h"

#include <glm/gtc/matrix_transform.hpp>

namespace lumar {

glm::dmat3 environmentFromMarker()
{
    // Marker (x, y, z) with z up -> environment (x, z, -y) with y up: a -90 degree turn about x.
    return glm::dmat3(glm::rotate(glm::dmat4(1.0), glm::radians(-90.0), glm::dvec3(1, 0, 0)));
}

} // namespace lumar
