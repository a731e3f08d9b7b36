#include "phantom_model.h"

#include <stdexcept>

#include <glm/gtc/matrix_transform.hpp>

#include "gles_renderer/assets/builtin_shapes.h"
#include "object_placement.h"

namespace lumar {
namespace {

// Rx(+90°) exactly (no rounding of cos 90°): model +Y -> marker +Z, +Z -> -Y.
const glm::dmat4 kUpright(glm::dvec4(1, 0, 0, 0), glm::dvec4(0, 0, 1, 0), glm::dvec4(0, -1, 0, 0),
                          glm::dvec4(0, 0, 0, 1));

// The phantom's single material. A phantom shows the camera image where the camera sees it;
// elsewhere (and with rendering.phantoms_show_camera off) this colour, so a mesh's own
// materials and textures are replaced, keeping only whether it has double-sided surfaces.
void useConfiguredColour(GltfModel& model, const PhantomConfig& phantom)
{
    GltfMaterial material;
    material.name = phantom.name;
    material.baseColorFactor = glm::vec4(glm::vec3(phantom.color), 1.0f);
    material.metallicFactor = 0.0f;
    material.roughnessFactor = 1.0f;
    for (const GltfMaterial& m : model.materials)
        material.doubleSided = material.doubleSided || m.doubleSided;
    model.materials = {material};
    model.textures.clear();
    for (GltfPrimitive& primitive : model.primitives)
        primitive.material = 0;
}

glm::dmat4 centredPlacement(const PhantomConfig& phantom, const glm::dvec3& scale)
{
    glm::dmat4 m = glm::translate(glm::dmat4(1.0), phantom.offset);
    if (phantom.headingDeg != 0.0)
        m = glm::rotate(m, glm::radians(phantom.headingDeg), glm::dvec3(0, 0, 1));
    return glm::scale(m, scale);
}

} // namespace

PhantomModel makePhantomModel(const PhantomConfig& phantom)
{
    PhantomModel placed;
    if (phantom.shape == "box") {
        placed.model = makeCube();
        placed.markerFromModel = centredPlacement(phantom, phantom.size);
    } else if (phantom.shape == "plane") {
        placed.model = makePlane();
        placed.markerFromModel = centredPlacement(phantom, glm::dvec3(phantom.size.x, phantom.size.y, 1.0)) * kUpright;
    } else if (phantom.shape == "cylinder") {
        placed.model = makeCylinder();
        placed.markerFromModel = centredPlacement(phantom, phantom.size) * kUpright;
    } else if (phantom.shape == "mesh") {
        if (!phantom.mesh)
            throw std::logic_error("makePhantomModel: phantom '" + phantom.name + "' has no mesh loaded");
        placed.model = *phantom.mesh;
        ObjectConfig fitted;
        fitted.offset = phantom.offset;
        fitted.headingDeg = phantom.headingDeg;
        fitted.size = phantom.size.x;
        placed.markerFromModel = markerFromModel(fitted, placed.model.boundsMin, placed.model.boundsMax);
    } else {
        throw std::logic_error("makePhantomModel: unknown shape '" + phantom.shape + "'");
    }
    useConfiguredColour(placed.model, phantom);
    return placed;
}

} // namespace lumar
