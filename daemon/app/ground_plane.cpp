#include "ground_plane.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace lumar {
namespace {

// How far above or below the marker's plane a phantom's top still counts as that plane.
constexpr double kSamePlaneMetres = 0.005;
// The reach beyond the footprint: shadows three object heights long (a light 18 degrees
// above the horizon), at least one footprint (the contact darkening's reach).
constexpr double kShadowHeights = 3.0;

} // namespace

GltfModel makeGroundModel()
{
    GltfModel model;
    GltfPrimitive quad;
    quad.positions = {{-0.5f, -0.5f, 0.0f}, {0.5f, -0.5f, 0.0f}, {0.5f, 0.5f, 0.0f}, {-0.5f, 0.5f, 0.0f}};
    quad.normals.assign(4, glm::vec3(0.0f, 0.0f, 1.0f));
    quad.uvs = {{0.0f, 1.0f}, {1.0f, 1.0f}, {1.0f, 0.0f}, {0.0f, 0.0f}};
    quad.tangents.assign(4, glm::vec4(1.0f, 0.0f, 0.0f, 1.0f));
    quad.indices = {0, 1, 2, 0, 2, 3}; // counter-clockwise seen from +z
    quad.material = 0;
    model.primitives.push_back(quad);
    GltfMaterial material;
    material.name = "ground";
    material.doubleSided = true;
    model.materials.push_back(material);
    model.boundsMin = {-0.5f, -0.5f, 0.0f};
    model.boundsMax = {0.5f, 0.5f, 0.0f};
    return model;
}

std::optional<glm::dmat4> groundUnder(std::span<const PlacedBox> objects, std::span<const PhantomConfig> phantoms)
{
    constexpr double inf = std::numeric_limits<double>::infinity();
    glm::dvec3 low(inf), high(-inf);
    for (const PlacedBox& object : objects)
        for (int i = 0; i < 8; ++i) {
            const glm::dvec3 local((i & 1) ? object.boundsMax.x : object.boundsMin.x,
                                   (i & 2) ? object.boundsMax.y : object.boundsMin.y,
                                   (i & 4) ? object.boundsMax.z : object.boundsMin.z);
            const glm::dvec3 p(object.markerFromModel * glm::dvec4(local, 1.0));
            if (std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z)) {
                low = glm::min(low, p);
                high = glm::max(high, p);
            }
        }
    if (!(low.x <= high.x))
        return std::nullopt;
    const glm::dvec2 centre = 0.5 * (glm::dvec2(low) + glm::dvec2(high));
    for (const PhantomConfig& phantom : phantoms) {
        if (phantom.shape == "mesh")
            continue; // its extent needs the model; a mesh table leaves the ground in place
        // A plane has no thickness (its size.z is unused): its top is where it lies.
        const double top = phantom.offset.z + (phantom.shape == "plane" ? 0.0 : 0.5 * phantom.size.z);
        const glm::dvec2 halfSize = 0.5 * glm::dvec2(phantom.size);
        if (std::abs(top) <= kSamePlaneMetres && std::abs(centre.x - phantom.offset.x) <= halfSize.x &&
            std::abs(centre.y - phantom.offset.y) <= halfSize.y)
            return std::nullopt;
    }
    const glm::dvec2 footprint = glm::dvec2(high) - glm::dvec2(low);
    const double reach = std::max(std::max(footprint.x, footprint.y), kShadowHeights * std::max(high.z, 0.0));
    glm::dmat4 markerFromModel(1.0);
    markerFromModel[0][0] = footprint.x + 2.0 * reach;
    markerFromModel[1][1] = footprint.y + 2.0 * reach;
    markerFromModel[3] = glm::dvec4(centre, 0.0, 1.0);
    return markerFromModel;
}

} // namespace lumar
