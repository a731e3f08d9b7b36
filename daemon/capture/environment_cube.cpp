#include "capture/environment_cube.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <thread>

#include <glm/gtc/type_ptr.hpp>

#include "core/environment_frame.h"
#include "core/error.h"

namespace lumar {
namespace {

constexpr float kPi = 3.14159265358979323846f;

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
    r = ay > ax ? 0.5f * kPi - r : r;
    r = x < 0.0f ? kPi - r : r;
    return y < 0.0f ? -r : r;
}

// Where direction e (environment frame, +Y up) falls in the map, in pixels: x from the left
// edge (unwrapped), y from the top, pixel centres at half-integers (environment_map.h).
[[gnu::always_inline]] inline glm::vec2 equirectPixel(const glm::vec3& e, int width, int height)
{
    const float u = 0.5f + fastAtan2(e.z, e.x) * (0.5f / kPi);
    const float v = fastAtan2(std::sqrt(e.x * e.x + e.z * e.z), e.y) * (1.0f / kPi);
    return {u * float(width) - 0.5f, v * float(height) - 0.5f};
}

// Bilinear lookup at pixel position p (equirectPixel), wrapping in longitude and clamping at
// the poles.
glm::vec3 sampleEquirect(const ImageF& map, glm::vec2 p)
{
    const float py = std::clamp(p.y, 0.0f, float(map.height - 1));
    const float fx0 = std::floor(p.x);
    const float wx = p.x - fx0;
    const int y0 = std::min(int(py), map.height - 1);
    const int y1 = std::min(y0 + 1, map.height - 1);
    const float wy = py - float(y0);
    int x0 = int(fx0);
    x0 = x0 < 0 ? x0 + map.width : (x0 >= map.width ? x0 - map.width : x0);
    const int x1 = x0 + 1 == map.width ? 0 : x0 + 1;
    const float* r0 = map.row(y0);
    const float* r1 = map.row(y1);
    const glm::vec3 a = glm::make_vec3(r0 + 3 * x0);
    const glm::vec3 b = glm::make_vec3(r0 + 3 * x1);
    const glm::vec3 c = glm::make_vec3(r1 + 3 * x0);
    const glm::vec3 d = glm::make_vec3(r1 + 3 * x1);
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

EnvironmentCube::EnvironmentCube(ImageF equirect, int log2Size)
    : equirect_(std::move(equirect)), log2Size_(std::clamp(log2Size, kMinLog2Size, kMaxLog2Size)),
      size_(1 << log2Size_), environmentFromWorld_(environmentFromMarker())
{
    if (equirect_.channels != 3 || equirect_.width < 2 || equirect_.height < 2) {
        throw InputError("the fake camera's environment map must be an RGB image of at least 2x2 pixels");
    }
}

glm::vec3 EnvironmentCube::radiance(const glm::vec3& d) const
{
    return sampleEquirect(equirect_, equirectPixel(environmentFromWorld_ * d, equirect_.width, equirect_.height));
}

PackedBuffer EnvironmentCube::bake(float exposure, const SrgbEncoder& encoder) const
{
    PackedBuffer texels = allocatePacked(6 * size_t(size_) * size_t(size_));
    // Faces are independent: one thread each, up to the cores there are (the result does not
    // depend on how many).
    const unsigned threads = std::clamp(std::thread::hardware_concurrency(), 1u, 6u);
    std::vector<std::thread> workers;
    for (unsigned t = 1; t < threads; ++t) {
        workers.emplace_back([&, t] {
            for (unsigned face = t; face < 6; face += threads) {
                bakeFace(int(face), exposure, encoder, texels.get());
            }
        });
    }
    for (unsigned face = 0; face < 6; face += threads) {
        bakeFace(int(face), exposure, encoder, texels.get());
    }
    for (std::thread& worker : workers) {
        worker.join();
    }
    return texels;
}

void EnvironmentCube::bakeFace(int face, float exposure, const SrgbEncoder& encoder,
                               fake_scene::PackedRgb* texels) const
{
    const int n = size_;
    const float step = 2.0f / float(n);
    const int axis = face / 2;
    // The other two axes in x, y, z order: what index() calls first and second.
    const int firstAxis = axis == 0 ? 1 : 0;
    const int secondAxis = axis == 2 ? 1 : 2;
    glm::vec3 major(0.0f);
    major[axis] = face % 2 == 0 ? 1.0f : -1.0f;
    glm::vec3 first(0.0f);
    first[firstAxis] = 1.0f;
    glm::vec3 second(0.0f);
    second[secondAxis] = 1.0f;
    // In the map's frame: e = m · (major + a · first + b · second).
    const glm::mat3& m = environmentFromWorld_;
    const glm::vec3 eMajor = m * major;
    const glm::vec3 eFirst = m * first;
    const glm::vec3 eSecond = m * second;
    const int width = equirect_.width;
    const int height = equirect_.height;
    std::array<float, size_t(1) << kMaxLog2Size> px;
    std::array<float, size_t(1) << kMaxLog2Size> py;
    for (int j = 0; j < n; ++j) {
        const float b = -1.0f + (float(j) + 0.5f) * step;
        const glm::vec3 rowBase = eMajor + b * eSecond;
        // Positions first, in a loop the compiler vectorizes; then the lookups.
        float* xs = px.data();
        float* ys = py.data();
        for (int i = 0; i < n; ++i) {
            const float a = -1.0f + (float(i) + 0.5f) * step;
            const glm::vec2 p = equirectPixel(rowBase + a * eFirst, width, height);
            xs[i] = p.x;
            ys[i] = p.y;
        }
        fake_scene::PackedRgb* row = texels + (size_t(face) * size_t(n) + size_t(j)) * size_t(n);
        for (int i = 0; i < n; ++i) {
            row[i] = encoder.pack(exposure * sampleEquirect(equirect_, {xs[i], ys[i]}));
        }
    }
}

} // namespace lumar
