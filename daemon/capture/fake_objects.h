// Real objects standing on the fake table ([[camera.fake_objects]]): boxes and upright
// cylinders, each placed in a fake tag's frame (the world frame moved to the tag's centre) and
// turned about z. Geometry only — ray hits, world bounds, and the outlines their shadows on
// the table are rasterised from; fake_camera.cpp shades them.
#pragma once

#include <array>
#include <cmath>
#include <vector>

#include <glm/glm.hpp>

#include "config/config.h"

namespace lumar {

struct FakeObjectHit {
    float t = INFINITY;    // along the ray, in units of the ray direction's length
    glm::vec3 local{0.0f}; // the hit point in the object's frame (footprint centre, turned)
    int face = -1;         // kSideX..kTop
    int object = -1;       // index of the object hit
};

class FakeObject {
public:
    // Box faces by outward normal in the object's frame; a cylinder has kSide and kTop only.
    static constexpr int kPlusX = 0, kMinusX = 1, kPlusY = 2, kMinusY = 3, kTop = 4, kBottom = 5, kSide = 0;
    static constexpr int kFaces = 6;

    // `tagPosition`: the centre of the tag it stands on, world metres.
    FakeObject(const FakeObjectConfig& config, const glm::dvec2& tagPosition);

    // The nearest hit of the ray eye + t·d, t > 0, if it is nearer than hit.t: updates `hit`
    // (object left for the caller) and returns true. A ray from inside the object misses.
    bool intersect(const glm::vec3& eye, const glm::vec3& d, FakeObjectHit& hit) const;

    // The outward unit normal at a hit, world frame.
    [[nodiscard]] glm::vec3 normal(const FakeObjectHit& hit) const;
    // Texture coordinates of a hit, [0, 1]², v = 0 at the image's top row: each face shows the
    // whole image upright as seen from outside (a cylinder's side wraps it once around).
    [[nodiscard]] glm::vec2 uv(const FakeObjectHit& hit) const;
    // The outward unit normal of a flat face, world frame.
    [[nodiscard]] glm::vec3 faceNormal(int face) const;

    // The 8 corners of its world-space bounding box.
    [[nodiscard]] std::array<glm::vec3, 8> boundsCorners() const;
    // World points whose convex hull contains the object (the box's corners, the cylinder's
    // rims as circumscribed polygons): what its shadow outline is projected from.
    [[nodiscard]] std::vector<glm::vec3> hullPoints() const;

    [[nodiscard]] bool isCylinder() const { return cylinder_; }

private:
    [[nodiscard]] glm::vec3 toLocal(const glm::vec3& v) const
    {
        return {cosHeading_ * v.x + sinHeading_ * v.y, -sinHeading_ * v.x + cosHeading_ * v.y, v.z};
    }
    [[nodiscard]] glm::vec3 toWorld(const glm::vec3& v) const
    {
        return {cosHeading_ * v.x - sinHeading_ * v.y, sinHeading_ * v.x + cosHeading_ * v.y, v.z};
    }

    bool cylinder_ = false;
    glm::vec3 centre_{0.0f}; // footprint centre, world (z = 0)
    glm::vec3 half_{0.0f};   // half extents along local x, y; z: the full height
    float cosHeading_ = 1.0f;
    float sinHeading_ = 0.0f;
};

} // namespace lumar
