#include "capture/environment_cube.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <thread>

#include "core/environment_frame.h"
#include "core/error.h"

namespace lumar {
namespace {

// atan2 within 1e-5 rad (a 7th-order minimax fit of atan on [0, 1]), branch-free so the
// bake's direction loop vectorizes: the map's texels are 6e-3 rad, and std::atan2 made the
// 6-million-texel bake several times slower.
[[gnu::always_inline]] inline float fastAtan2(float y, float x)
{
    const float ax = std::abs(x);
    const float ay = std::abs(y);
    const float a = std::min(ax, ay) / std::max(std::max(ax, ay), 1e-30f);
    const float s = a * a;
    float r = ((-0.0464964749f * s + 0.15931422f) * s - 0.327622764f) * s * a + a;
    r = ay > ax ? 0.5f * std::numbers::pi_v<float> - r : r;
    r = x < 0.0f ? std::numbers::pi_v<float> - r : r;
    return y < 0.0f ? -r : r;
}

// Where direction e (environment frame, +Y up) falls in the map, in pixels: x from the left
// edge (unwrapped), y from the top, pixel centres at half-integers (environment_map.h).
[[gnu::always_inline]] inline glm::vec2 equirectPixel(const glm::vec3& e, int width, int height)
{
    const float u = 0.5f + fastAtan2(e.z, e.x) * (0.5f / std::numbers::pi_v<float>);
    const float v = fastAtan2(std::sqrt(e.x * e.x + e.z * e.z), e.y) * (1.0f / std::numbers::pi_v<float>);
    return {u * float(width) - 0.5f, v * float(height) - 0.5f};
}

// Bilinear lookup at pixel position p (equirectPixel), wrapping in longitude and clamping at
// the poles.
glm::vec3 sampleEquirect(const SharedExponentImage& map, glm::vec2 p)
{
    const int width = map.width();
    const int height = map.height();
    const float py = std::clamp(p.y, 0.0f, float(height - 1));
    const float fx0 = std::floor(p.x);
    const float wx = p.x - fx0;
    const int y0 = std::min(int(py), height - 1);
    const int y1 = std::min(y0 + 1, height - 1);
    const float wy = py - float(y0);
    int x0 = int(fx0);
    x0 = x0 < 0 ? x0 + width : (x0 >= width ? x0 - width : x0);
    const int x1 = x0 + 1 == width ? 0 : x0 + 1;
    const glm::vec3 a = map.at(x0, y0);
    const glm::vec3 b = map.at(x1, y0);
    const glm::vec3 c = map.at(x0, y1);
    const glm::vec3 d = map.at(x1, y1);
    const glm::vec3 top = a + wx * (b - a);
    const glm::vec3 bottom = c + wx * (d - c);
    return top + wy * (bottom - top);
}

} // namespace

int EnvironmentCube::log2SizeFor(double fx)
{
    int log2 = kMinLog2Size;
    while (log2 < kMaxLog2Size && double(1 << log2) < fx) {
        ++log2;
    }
    return log2;
}

namespace {

const ImageF& checkedMap(const ImageF& equirect)
{
    if (equirect.channels != 3 || equirect.width < 2 || equirect.height < 2) {
        throw InputError("the fake camera's environment map must be an RGB image of at least 2x2 pixels");
    }
    return equirect;
}

} // namespace

EnvironmentCube::EnvironmentCube(const ImageF& equirect, float intensity, int log2Size)
    : equirect_(checkedMap(equirect), intensity), log2Size_(std::clamp(log2Size, kMinLog2Size, kMaxLog2Size)),
      size_(1 << log2Size_), environmentFromWorld_(environmentFromMarker()), tileCones_(makeTileCones())
{
}

EnvironmentCube::FaceAxes EnvironmentCube::worldAxes(int face)
{
    const int axis = face / 2;
    // The other two axes in x, y, z order: what index() calls first and second.
    const int firstAxis = axis == 0 ? 1 : 0;
    const int secondAxis = axis == 2 ? 1 : 2;
    FaceAxes axes;
    axes.major[axis] = face % 2 == 0 ? 1.0f : -1.0f;
    axes.first[firstAxis] = 1.0f;
    axes.second[secondAxis] = 1.0f;
    return axes;
}

std::vector<EnvironmentCube::TileCone> EnvironmentCube::makeTileCones() const
{
    const int tilesPerSide = size_ >> kLog2Tile;
    const double texel = 2.0 / double(size_);
    std::vector<TileCone> cones;
    cones.reserve(size_t(6 * tilesPerSide * tilesPerSide));
    for (int face = 0; face < 6; ++face) {
        const FaceAxes axes = worldAxes(face);
        const auto direction = [&](double a, double b) {
            return glm::normalize(glm::dvec3(axes.major) + a * glm::dvec3(axes.first) + b * glm::dvec3(axes.second));
        };
        for (int tj = 0; tj < tilesPerSide; ++tj) {
            for (int ti = 0; ti < tilesPerSide; ++ti) {
                // The tile's face coordinates, a texel wider all round: index() rounds a direction
                // on a border either way, and one on a face's edge may go to either face.
                const double a0 = -1.0 + double(ti << kLog2Tile) * texel - texel;
                const double a1 = -1.0 + double((ti + 1) << kLog2Tile) * texel + texel;
                const double b0 = -1.0 + double(tj << kLog2Tile) * texel - texel;
                const double b1 = -1.0 + double((tj + 1) << kLog2Tile) * texel + texel;
                const glm::dvec3 centre = direction(0.5 * (a0 + a1), 0.5 * (b0 + b1));
                // The rectangle lies inside the circle of directions within the largest corner's
                // angle (the circle meets the face's plane in a convex conic).
                double cosRadius = 1.0;
                for (const glm::dvec2 corner :
                     {glm::dvec2(a0, b0), glm::dvec2(a1, b0), glm::dvec2(a0, b1), glm::dvec2(a1, b1)}) {
                    cosRadius = std::min(cosRadius, glm::dot(centre, direction(corner.x, corner.y)));
                }
                cones.push_back({glm::vec3(centre), float(std::sqrt(std::max(0.0, 1.0 - cosRadius * cosRadius)))});
            }
        }
    }
    return cones;
}

bool EnvironmentCube::tileMayBeSeen(int tile, const ViewCone& view) const
{
    // A direction d inside the view and within the tile's radius r of its centre c: each side's
    // inward normal n has n · d >= 0, so n · c >= -sin r. The slack covers float rounding.
    constexpr float kSlack = 1e-4f;
    const TileCone& cone = tileCones_[size_t(tile)];
    for (const glm::vec3& n : view.inward) {
        if (glm::dot(n, cone.centre) < -cone.sinRadius - kSlack) {
            return false;
        }
    }
    return true;
}

bool EnvironmentCube::tileWithin(int tile, const ViewCone& cone) const
{
    // Every direction within the tile's radius r of its centre c lies inside a side with
    // inward normal n if n · c >= sin r.
    constexpr float kSlack = 1e-4f;
    const TileCone& t = tileCones_[size_t(tile)];
    for (const glm::vec3& n : cone.inward) {
        if (glm::dot(n, t.centre) < t.sinRadius + kSlack) {
            return false;
        }
    }
    return true;
}

glm::vec3 EnvironmentCube::radiance(const glm::vec3& d) const
{
    return sampleEquirect(equirect_, equirectPixel(environmentFromWorld_ * d, equirect_.width(), equirect_.height()));
}

PackedBuffer EnvironmentCube::bake(float exposure, const SrgbEncoder& encoder) const
{
    PackedBuffer texels = allocatePacked(texelCount());
    // Tiles are independent: interleaved over up to the cores there are (the result does not
    // depend on how many).
    const unsigned threads = std::clamp(std::thread::hardware_concurrency(), 1u, 6u);
    const auto bakeEvery = [&](unsigned first) {
        for (int tile = int(first); tile < tileCount(); tile += int(threads)) {
            bakeTile(tile, exposure, encoder, texels.get());
        }
    };
    std::vector<std::thread> workers;
    for (unsigned t = 1; t < threads; ++t) {
        workers.emplace_back(bakeEvery, t);
    }
    bakeEvery(0);
    for (std::thread& worker : workers) {
        worker.join();
    }
    return texels;
}

void EnvironmentCube::bakeTile(int tile, float exposure, const SrgbEncoder& encoder,
                               fake_scene::PackedRgb* texels) const
{
    constexpr int kSide = 1 << kLog2Tile;
    const int n = size_;
    const int tilesPerSide = n >> kLog2Tile;
    const int face = tile / (tilesPerSide * tilesPerSide);
    const int j0 = (tile / tilesPerSide % tilesPerSide) << kLog2Tile;
    const int i0 = (tile % tilesPerSide) << kLog2Tile;
    const float step = 2.0f / float(n);
    const FaceAxes axes = worldAxes(face);
    // In the map's frame: e = m · (major + a · first + b · second).
    const glm::mat3& m = environmentFromWorld_;
    const glm::vec3 eMajor = m * axes.major;
    const glm::vec3 eFirst = m * axes.first;
    const glm::vec3 eSecond = m * axes.second;
    const int width = equirect_.width();
    const int height = equirect_.height();
    std::array<float, kSide> px;
    std::array<float, kSide> py;
    fake_scene::PackedRgb* out = texels + size_t(tile) * kTileTexels;
    for (int j = j0; j < j0 + kSide; ++j) {
        const float b = -1.0f + (float(j) + 0.5f) * step;
        const glm::vec3 rowBase = eMajor + b * eSecond;
        // Positions first, in a loop the compiler vectorizes; then the lookups.
        float* xs = px.data();
        float* ys = py.data();
        for (int k = 0; k < kSide; ++k) {
            const float a = -1.0f + (float(i0 + k) + 0.5f) * step;
            const glm::vec2 p = equirectPixel(rowBase + a * eFirst, width, height);
            xs[k] = p.x;
            ys[k] = p.y;
        }
        fake_scene::PackedRgb* row = out + size_t(j - j0) * kSide;
        for (int k = 0; k < kSide; ++k) {
            row[k] = encoder.pack(exposure * sampleEquirect(equirect_, {xs[k], ys[k]}));
        }
    }
}

} // namespace lumar
