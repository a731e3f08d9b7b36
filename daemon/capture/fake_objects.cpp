#include "capture/fake_objects.h"

#include <algorithm>

namespace lumar {
namespace {

constexpr float kPi = 3.14159265358979323846f;
// Rim points of a cylinder's shadow outline: the polygon's flats are 0.2 % of the radius in.
constexpr int kRimPoints = 48;

} // namespace

FakeObject::FakeObject(const FakeObjectConfig& config, const glm::dvec2& tagPosition)
    : cylinder_(config.shape == "cylinder"), centre_(glm::vec3(glm::vec2(tagPosition + config.offset), 0.0f)),
      half_(float(0.5 * config.size.x), float(0.5 * config.size.y), float(config.size.z)),
      cosHeading_(float(std::cos(config.headingDeg * double(kPi) / 180.0))),
      sinHeading_(float(std::sin(config.headingDeg * double(kPi) / 180.0)))
{
}

bool FakeObject::intersect(const glm::vec3& eye, const glm::vec3& d, FakeObjectHit& hit) const
{
    const glm::vec3 p = toLocal(eye - centre_);
    const glm::vec3 v = toLocal(d);
    float t = INFINITY;
    int face = -1;
    if (cylinder_) {
        const float r = half_.x;
        const float a = v.x * v.x + v.y * v.y;
        const float b = p.x * v.x + p.y * v.y;
        const float c = p.x * p.x + p.y * p.y - r * r;
        const float disc = b * b - a * c;
        if (a > 0.0f && disc >= 0.0f && c > 0.0f) {
            const float ts = (-b - std::sqrt(disc)) / a;
            const float z = p.z + ts * v.z;
            if (ts > 0.0f && z >= 0.0f && z <= half_.z) {
                t = ts;
                face = kSide;
            }
        }
        if (v.z < 0.0f && p.z > half_.z) {
            const float tt = (half_.z - p.z) / v.z;
            const float x = p.x + tt * v.x;
            const float y = p.y + tt * v.y;
            if (tt < t && x * x + y * y <= r * r) {
                t = tt;
                face = kTop;
            }
        }
    } else {
        // Slabs: the ray is inside all three between tNear and tFar.
        const float lo[3] = {-half_.x, -half_.y, 0.0f};
        const float hi[3] = {half_.x, half_.y, half_.z};
        float tNear = -INFINITY;
        float tFar = INFINITY;
        for (int axis = 0; axis < 3; ++axis) {
            if (v[axis] == 0.0f) {
                if (p[axis] < lo[axis] || p[axis] > hi[axis]) {
                    return false;
                }
                continue;
            }
            const float inv = 1.0f / v[axis];
            const float tLo = (lo[axis] - p[axis]) * inv;
            const float tHi = (hi[axis] - p[axis]) * inv;
            // Entering through the low side when moving towards +axis.
            const float enter = v[axis] > 0.0f ? tLo : tHi;
            const float leave = v[axis] > 0.0f ? tHi : tLo;
            if (enter > tNear) {
                tNear = enter;
                face = 2 * axis + (v[axis] > 0.0f ? 1 : 0);
            }
            tFar = std::min(tFar, leave);
        }
        if (tNear > tFar || !(tNear > 0.0f)) {
            return false;
        }
        t = tNear;
    }
    if (face < 0 || !(t < hit.t)) {
        return false;
    }
    hit.t = t;
    hit.local = p + t * v;
    hit.face = face;
    return true;
}

glm::vec3 FakeObject::faceNormal(int face) const
{
    static constexpr glm::vec3 kNormals[kFaces] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
    return toWorld(kNormals[face]);
}

glm::vec3 FakeObject::normal(const FakeObjectHit& hit) const
{
    if (cylinder_ && hit.face == kSide) {
        const glm::vec2 radial = glm::normalize(glm::vec2(hit.local));
        return toWorld(glm::vec3(radial, 0.0f));
    }
    return faceNormal(hit.face);
}

glm::vec2 FakeObject::uv(const FakeObjectHit& hit) const
{
    const glm::vec3& q = hit.local;
    const float down = std::clamp(1.0f - q.z / half_.z, 0.0f, 1.0f); // 0 at the top edge
    if (hit.face == kTop || hit.face == kBottom) {
        // Seen from above: image right along +x, image up along +y.
        return {std::clamp(0.5f + 0.5f * q.x / half_.x, 0.0f, 1.0f),
                std::clamp(0.5f - 0.5f * q.y / half_.y, 0.0f, 1.0f)};
    }
    if (cylinder_) {
        // Once around, rightwards as seen from outside (counter-clockwise from above).
        const float angle = std::atan2(q.y, q.x);
        return {std::clamp(0.5f + angle * (0.5f / kPi), 0.0f, 1.0f), down};
    }
    // Seen from outside along −n with z up, image right is −n × z.
    float across = 0.0f;
    switch (hit.face) {
    case kPlusX:
        across = q.y / half_.y;
        break;
    case kMinusX:
        across = -q.y / half_.y;
        break;
    case kPlusY:
        across = -q.x / half_.x;
        break;
    default:
        across = q.x / half_.x;
        break;
    }
    return {std::clamp(0.5f + 0.5f * across, 0.0f, 1.0f), down};
}

std::array<glm::vec3, 8> FakeObject::boundsCorners() const
{
    std::array<glm::vec3, 8> corners{};
    for (int i = 0; i < 8; ++i) {
        const glm::vec3 local((i & 1) ? half_.x : -half_.x, (i & 2) ? half_.y : -half_.y, (i & 4) ? half_.z : 0.0f);
        corners[size_t(i)] = centre_ + toWorld(local);
    }
    return corners;
}

std::vector<glm::vec3> FakeObject::hullPoints() const
{
    if (!cylinder_) {
        const auto corners = boundsCorners();
        return {corners.begin(), corners.end()};
    }
    std::vector<glm::vec3> points;
    points.reserve(2 * kRimPoints);
    const float r = half_.x / std::cos(kPi / kRimPoints); // circumscribed
    for (int i = 0; i < kRimPoints; ++i) {
        const float a = 2.0f * kPi * float(i) / kRimPoints;
        const glm::vec3 rim(r * std::cos(a), r * std::sin(a), 0.0f);
        points.push_back(centre_ + rim);
        points.push_back(centre_ + rim + glm::vec3(0.0f, 0.0f, half_.z));
    }
    return points;
}

} // namespace lumar
