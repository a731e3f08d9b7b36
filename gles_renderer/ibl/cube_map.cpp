#include "gles_renderer/ibl/cube_map.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>

#include "core/error.h"

namespace lumar {
namespace {

void checkFace(int face)
{
    if (face < 0 || face > 5) {
        throw InputError("cube face must be in 0..5, got " + std::to_string(face));
    }
}

void checkCubeSize(int size)
{
    if (size < 1 || size > kMaxCubeSize) {
        throw InputError("cube face size must be in [1, " + std::to_string(kMaxCubeSize) + "], got " +
                         std::to_string(size));
    }
}

} // namespace

float maxComponent(const CubeMapF& cube)
{
    float m = 0.0f;
    for (const ImageF& face : cube.faces)
        for (const float v : face.data)
            m = std::max(m, v);
    return m;
}

void checkCubeMap(const CubeMapF& cube)
{
    checkCubeSize(cube.size);
    for (const ImageF& face : cube.faces) {
        if (face.width != cube.size || face.height != cube.size || face.channels != 3 ||
            face.data.size() != size_t(cube.size) * size_t(cube.size) * 3) {
            throw InputError("cube faces must all be " + std::to_string(cube.size) + "x" + std::to_string(cube.size) +
                             "x3");
        }
    }
}

namespace {

glm::vec3 texel(const ImageF& face, int x, int y)
{
    const float* p = face.at(x, y);
    return {p[0], p[1], p[2]};
}

// The signed solid angle of the face rectangle between the face centre and the corner (u, v),
// for a face at distance 1: atan(uv / √(u² + v² + 1)).
double cornerSolidAngle(double u, double v)
{
    return std::atan2(u * v, std::sqrt(u * u + v * v + 1.0));
}

// Bilinear weights and the two clamped indices along one axis of a face.
struct Lerp {
    int i0, i1;
    float f;
};

Lerp clampedLerp(float coordinate, int size)
{
    const float p = std::clamp(coordinate * float(size) - 0.5f, 0.0f, float(size - 1));
    const int i0 = std::min(int(p), size - 1);
    return {i0, std::min(i0 + 1, size - 1), p - float(i0)};
}

} // namespace

glm::vec3 cubeTexelDirection(int face, float s, float t)
{
    checkFace(face);
    const float sc = 2.0f * s - 1.0f;
    const float tc = 2.0f * t - 1.0f;
    // The face table of cube_map.h solved for r with |ma| = 1.
    switch (face) {
    case 0:
        return glm::normalize(glm::vec3(1.0f, -tc, -sc));
    case 1:
        return glm::normalize(glm::vec3(-1.0f, -tc, sc));
    case 2:
        return glm::normalize(glm::vec3(sc, 1.0f, tc));
    case 3:
        return glm::normalize(glm::vec3(sc, -1.0f, -tc));
    case 4:
        return glm::normalize(glm::vec3(sc, -tc, 1.0f));
    default:
        return glm::normalize(glm::vec3(-sc, -tc, -1.0f));
    }
}

glm::vec3 cubeTexelCentreDirection(int face, int size, int x, int y)
{
    return cubeTexelDirection(face, (float(x) + 0.5f) / float(size), (float(y) + 0.5f) / float(size));
}

CubeCoord cubeCoordinate(const glm::vec3& dir)
{
    const glm::vec3 a = glm::abs(dir);
    if (!std::isfinite(a.x) || !std::isfinite(a.y) || !std::isfinite(a.z) || (a.x == 0 && a.y == 0 && a.z == 0)) {
        throw InputError("cube lookup needs a finite non-zero direction");
    }
    int face;
    float sc, tc, ma;
    if (a.x >= a.y && a.x >= a.z) {
        face = dir.x > 0 ? 0 : 1;
        sc = dir.x > 0 ? -dir.z : dir.z;
        tc = -dir.y;
        ma = a.x;
    } else if (a.y >= a.z) {
        face = dir.y > 0 ? 2 : 3;
        sc = dir.x;
        tc = dir.y > 0 ? dir.z : -dir.z;
        ma = a.y;
    } else {
        face = dir.z > 0 ? 4 : 5;
        sc = dir.z > 0 ? dir.x : -dir.x;
        tc = -dir.y;
        ma = a.z;
    }
    return {face, 0.5f * (sc / ma + 1.0f), 0.5f * (tc / ma + 1.0f)};
}

glm::vec3 sampleCubeBilinear(const CubeMapF& cube, const glm::vec3& dir)
{
    checkCubeMap(cube);
    const CubeCoord c = cubeCoordinate(dir);
    const ImageF& face = cube.faces[size_t(c.face)];
    const Lerp x = clampedLerp(c.s, cube.size);
    const Lerp y = clampedLerp(c.t, cube.size);
    const glm::vec3 top = glm::mix(texel(face, x.i0, y.i0), texel(face, x.i1, y.i0), x.f);
    const glm::vec3 bottom = glm::mix(texel(face, x.i0, y.i1), texel(face, x.i1, y.i1), x.f);
    return glm::mix(top, bottom, y.f);
}

glm::vec3 sampleCubeNearest(const CubeMapF& cube, const glm::vec3& dir)
{
    checkCubeMap(cube);
    const CubeCoord c = cubeCoordinate(dir);
    const int x = std::clamp(int(std::floor(c.s * float(cube.size))), 0, cube.size - 1);
    const int y = std::clamp(int(std::floor(c.t * float(cube.size))), 0, cube.size - 1);
    return texel(cube.faces[size_t(c.face)], x, y);
}

CubeMapF cubeFromFunction(int size, const std::function<glm::vec3(glm::vec3)>& radiance)
{
    checkCubeSize(size);
    CubeMapF cube;
    cube.size = size;
    for (int f = 0; f < 6; ++f) {
        ImageF& face = cube.faces[size_t(f)];
        face.reshape(size, size, 3);
        for (int y = 0; y < size; ++y) {
            for (int x = 0; x < size; ++x) {
                const glm::vec3 value = radiance(cubeTexelCentreDirection(f, size, x, y));
                float* p = face.at(x, y);
                p[0] = value.x;
                p[1] = value.y;
                p[2] = value.z;
            }
        }
    }
    return cube;
}

glm::vec3 sampleEquirectBilinear(const ImageF& equirect, const glm::vec3& dir)
{
    constexpr float pi = std::numbers::pi_v<float>;
    if (equirect.channels != 3 || equirect.width < 1 || equirect.height < 1 ||
        equirect.data.size() != size_t(equirect.width) * size_t(equirect.height) * 3) {
        throw InputError("equirectangular lookup needs a non-empty 3-channel image");
    }
    const float length = glm::length(dir);
    if (!std::isfinite(length) || length == 0.0f) {
        throw InputError("equirectangular lookup needs a finite non-zero direction");
    }
    const glm::vec3 d = dir / length;
    const float u = 0.5f + std::atan2(d.z, d.x) / (2.0f * pi);
    const float v = std::acos(std::clamp(d.y, -1.0f, 1.0f)) / pi;
    // Longitude wraps: the column left of column 0 is the last one.
    const float px = u * float(equirect.width) - 0.5f;
    const float x0f = std::floor(px);
    const float fx = px - x0f;
    const int w = equirect.width;
    const int x0 = ((int(x0f) % w) + w) % w;
    const int x1 = (x0 + 1) % w;
    const Lerp y = clampedLerp(v, equirect.height);
    const glm::vec3 top = glm::mix(texel(equirect, x0, y.i0), texel(equirect, x1, y.i0), fx);
    const glm::vec3 bottom = glm::mix(texel(equirect, x0, y.i1), texel(equirect, x1, y.i1), fx);
    return glm::mix(top, bottom, y.f);
}

CubeMapF cubeFromEquirect(const ImageF& equirect, int size)
{
    // sampleEquirectBilinear checks the image (on the first texel).
    return cubeFromFunction(size, [&](glm::vec3 d) { return sampleEquirectBilinear(equirect, d); });
}

double texelSolidAngleExact(int size, int x, int y)
{
    const double u0 = 2.0 * x / size - 1.0, u1 = 2.0 * (x + 1) / size - 1.0;
    const double v0 = 2.0 * y / size - 1.0, v1 = 2.0 * (y + 1) / size - 1.0;
    // Inclusion–exclusion over the four corner rectangles anchored at the face centre.
    return cornerSolidAngle(u1, v1) - cornerSolidAngle(u0, v1) - cornerSolidAngle(u1, v0) + cornerSolidAngle(u0, v0);
}

double texelSolidAngleKing(int size, int x, int y)
{
    const double u = 2.0 * (x + 0.5) / size - 1.0;
    const double v = 2.0 * (y + 0.5) / size - 1.0;
    const double r2 = u * u + v * v + 1.0;
    return 4.0 / (double(size) * double(size) * r2 * std::sqrt(r2));
}

} // namespace lumar
