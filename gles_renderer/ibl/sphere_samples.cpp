#include "gles_renderer/ibl/sphere_samples.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <random>
#include <string>

#include "core/error.h"

namespace lumar {
namespace {

constexpr double kTwoPi = 2.0 * std::numbers::pi;

void checkGridSide(int gridSide)
{
    if (gridSide < 1 || gridSide > kMaxSampleGridSide) {
        throw InputError("sample grid side must be in [1, " + std::to_string(kMaxSampleGridSide) + "], got " +
                         std::to_string(gridSide));
    }
}

// A float in [0, 1) from the top 24 bits of one 32-bit word: every value is exactly
// representable, so the result depends on the engine's output only.
double unitFloat(std::mt19937& engine)
{
    return double(engine() >> 8) * 0x1.0p-24;
}

// Calls emit(x, y) for the jittered centre of every grid cell, in index order.
template <typename Emit> void jitteredGrid(int gridSide, uint32_t seed, Emit&& emit)
{
    std::mt19937 engine(seed);
    for (int j = 0; j < gridSide; ++j) {
        for (int i = 0; i < gridSide; ++i) {
            const double x = (i + unitFloat(engine)) / gridSide;
            const double y = (j + unitFloat(engine)) / gridSide;
            emit(x, y);
        }
    }
}

} // namespace

std::vector<glm::vec3> stratifiedSphereSamples(int gridSide, uint32_t seed)
{
    checkGridSide(gridSide);
    std::vector<glm::vec3> directions;
    directions.reserve(size_t(gridSide) * size_t(gridSide));
    jitteredGrid(gridSide, seed, [&](double x, double y) {
        // θ = 2·acos(√(1 − x)) gives cosθ = 1 − 2x and sinθ = 2√(x(1 − x)); the second form
        // keeps full precision near the poles, where 1 − cos²θ would cancel.
        const double cosTheta = 1.0 - 2.0 * x;
        const double sinTheta = 2.0 * std::sqrt(x * (1.0 - x));
        const double phi = kTwoPi * y;
        directions.emplace_back(sinTheta * std::cos(phi), cosTheta, sinTheta * std::sin(phi));
    });
    return directions;
}

std::vector<glm::vec3> fibonacciSphereSamples(int count)
{
    constexpr int kMaxCount = kMaxSampleGridSide * kMaxSampleGridSide;
    if (count < 1 || count > kMaxCount) {
        throw InputError("Fibonacci sample count must be in [1, " + std::to_string(kMaxCount) + "], got " +
                         std::to_string(count));
    }
    const double goldenAngle = std::numbers::pi * (3.0 - std::sqrt(5.0));
    std::vector<glm::vec3> directions;
    directions.reserve(size_t(count));
    for (int k = 0; k < count; ++k) {
        const double cosTheta = 1.0 - (2.0 * k + 1.0) / count;
        const double sinTheta = std::sqrt(std::max(0.0, 1.0 - cosTheta * cosTheta));
        // k · goldenAngle grows to ~4e7 rad; reducing it modulo 2π first keeps cos/sin exact.
        const double phi = std::fmod(k * goldenAngle, kTwoPi);
        directions.emplace_back(sinTheta * std::cos(phi), cosTheta, sinTheta * std::sin(phi));
    }
    return directions;
}

std::vector<glm::vec3> fibonacciCapSamples(int count, float cosMaxAngle)
{
    constexpr int kMaxCount = kMaxSampleGridSide * kMaxSampleGridSide;
    if (count < 1 || count > kMaxCount || !(cosMaxAngle >= -1.0f && cosMaxAngle < 1.0f)) {
        throw InputError("Fibonacci cap needs 1.." + std::to_string(kMaxCount) +
                         " samples and a cap cosine in [-1, 1), got " + std::to_string(count) + " and " +
                         std::to_string(cosMaxAngle));
    }
    const double goldenAngle = std::numbers::pi * (3.0 - std::sqrt(5.0));
    std::vector<glm::vec3> directions;
    directions.reserve(size_t(count));
    for (int k = 0; k < count; ++k) {
        const double cosTheta = 1.0 - (k + 0.5) * (1.0 - double(cosMaxAngle)) / count;
        const double sinTheta = std::sqrt(std::max(0.0, 1.0 - cosTheta * cosTheta));
        const double phi = std::fmod(k * goldenAngle, kTwoPi);
        directions.emplace_back(sinTheta * std::cos(phi), sinTheta * std::sin(phi), cosTheta);
    }
    return directions;
}

std::vector<glm::vec3> stratifiedCapSamples(int gridSide, float cosMaxAngle, uint32_t seed)
{
    checkGridSide(gridSide);
    if (!(cosMaxAngle >= -1.0f && cosMaxAngle < 1.0f)) {
        throw InputError("cap cosine must be in [-1, 1), got " + std::to_string(cosMaxAngle));
    }
    const double height = 1.0 - double(cosMaxAngle);
    std::vector<glm::vec3> directions;
    directions.reserve(size_t(gridSide) * size_t(gridSide));
    jitteredGrid(gridSide, seed, [&](double x, double y) {
        // 1 − cos²θ = (1 − cosθ)(1 + cosθ) = xh(2 − xh), again without cancellation near +Z.
        const double oneMinusCos = x * height;
        const double sinTheta = std::sqrt(std::max(0.0, oneMinusCos * (2.0 - oneMinusCos)));
        const double phi = kTwoPi * y;
        directions.emplace_back(sinTheta * std::cos(phi), sinTheta * std::sin(phi), 1.0 - oneMinusCos);
    });
    return directions;
}

std::vector<glm::vec3> powerCapSamples(int count, float exponent, float cosMaxAngle)
{
    constexpr int kMaxCount = kMaxSampleGridSide * kMaxSampleGridSide;
    if (count < 1 || count > kMaxCount || !(exponent >= 0.0f) || !(cosMaxAngle >= 0.0f && cosMaxAngle < 1.0f)) {
        throw InputError("power-cap samples need a count in 1.." + std::to_string(kMaxCount) +
                         ", an exponent >= 0 and a cap cosine in [0, 1), got " + std::to_string(count) + ", " +
                         std::to_string(exponent) + " and " + std::to_string(cosMaxAngle));
    }
    const double goldenAngle = std::numbers::pi * (3.0 - std::sqrt(5.0));
    const double power = double(exponent) + 1.0;
    const double mass = 1.0 - std::pow(double(cosMaxAngle), power); // of cos^(m+1) over the cap
    std::vector<glm::vec3> directions;
    directions.reserve(size_t(count));
    for (int k = 0; k < count; ++k) {
        const double u = (k + 0.5) / count;
        const double cosTheta = std::pow(1.0 - u * mass, 1.0 / power);
        const double sinTheta = std::sqrt(std::max(0.0, (1.0 - cosTheta) * (1.0 + cosTheta)));
        const double phi = std::fmod(k * goldenAngle, kTwoPi);
        directions.emplace_back(sinTheta * std::cos(phi), sinTheta * std::sin(phi), cosTheta);
    }
    return directions;
}

double powerCapPdf(double cosTheta, double exponent, double cosMaxAngle)
{
    if (!(cosTheta >= cosMaxAngle) || cosTheta > 1.0)
        return 0.0;
    return (exponent + 1.0) * std::pow(cosTheta, exponent) / (kTwoPi * (1.0 - std::pow(cosMaxAngle, exponent + 1.0)));
}

double capSolidAngle(float cosMaxAngle)
{
    return kTwoPi * (1.0 - double(cosMaxAngle));
}

} // namespace lumar
