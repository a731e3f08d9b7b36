// The receiver-only ground under the objects of one marker ([shadows] ground, DESIGN.md §6.5):
// objects usually stand on a real table that has no phantom, and without a surface to receive
// them their shadows and contact darkening would not show. The plane lies on the marker's
// plane (z = 0), centred under the objects' footprint and reaching beyond it far enough for
// the shadow of an object under a light 18 degrees above the horizon (three heights) and for
// the contact darkening to fade (one footprint).
#pragma once

#include <optional>
#include <span>

#include <glm/glm.hpp>

#include "config/config.h"
#include "gles_renderer/assets/gltf_model.h"

namespace lumar {

// An object's bounding box placed on the marker.
struct PlacedBox {
    glm::dmat4 markerFromModel{1.0};
    glm::vec3 boundsMin{0.0f}, boundsMax{0.0f};
};

// A single quad of side 1 in the plane z = 0 of its model frame, centred on the origin,
// facing +z: scaled and placed by groundUnder().
GltfModel makeGroundModel();

// markerFromModel of the ground quad under `objects` (all on one marker), or nullopt where
// there is nothing to stand on it, or where one of `phantoms` (those on the same marker)
// already is that surface: its top within 5 mm of the marker's plane under the footprint's
// centre (its receiver darkens the camera image there, a second surface would darken it twice).
std::optional<glm::dmat4> groundUnder(std::span<const PlacedBox> objects, std::span<const PhantomConfig> phantoms);

} // namespace lumar
