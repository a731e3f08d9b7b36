#include "gles_renderer/ibl/sh_projection.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <string>
#include <vector>

#include "core/error.h"

namespace lumar {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr int kMaxThetaSteps = 8192;

using SumSH9 = std::array<glm::dvec3, 9>;

void accumulate(SumSH9& sum, const glm::vec3& radiance, const glm::vec3& direction, double weight)
{
    const std::array<float, 9> y = shBasis(direction);
    const glm::dvec3 weighted = glm::dvec3(radiance) * weight;
    for (size_t k = 0; k < 9; ++k) {
        sum[k] += weighted * double(y[k]);
    }
}

SH9 toSH9(const SumSH9& sum)
{
    SH9 sh;
    for (size_t k = 0; k < 9; ++k) {
        sh[k] = glm::vec3(sum[k]);
    }
    return sh;
}

glm::vec3 texelValue(const ImageF& face, int x, int y)
{
    const float* p = face.at(x, y);
    return {p[0], p[1], p[2]};
}

// Σ over every texel of L · Y(texel centre) · weight(size, x, y).
template <typename Weight> SH9 projectCube(const CubeMapF& cube, Weight&& weight)
{
    checkCubeMap(cube);
    SumSH9 sum{};
    for (int f = 0; f < 6; ++f) {
        for (int y = 0; y < cube.size; ++y) {
            for (int x = 0; x < cube.size; ++x) {
                accumulate(sum, texelValue(cube.faces[size_t(f)], x, y), cubeTexelCentreDirection(f, cube.size, x, y),
                           weight(cube.size, x, y));
            }
        }
    }
    return toSH9(sum);
}

struct GaussNode {
    double x, w;
};

// Gauss–Legendre nodes and weights on [-1, 1]: Newton's method on P_n from the usual
// asymptotic first guess, P_n and P_n' by the three-term recurrence.
std::vector<GaussNode> gaussLegendre(int n)
{
    std::vector<GaussNode> nodes(static_cast<size_t>(n));
    for (int i = 0; i < (n + 1) / 2; ++i) {
        double x = std::cos(kPi * (i + 0.75) / (n + 0.5));
        double derivative = 1.0;
        for (int iteration = 0; iteration < 100; ++iteration) {
            double p0 = 1.0, p1 = x;
            for (int k = 2; k <= n; ++k) {
                const double p2 = ((2.0 * k - 1.0) * x * p1 - (k - 1.0) * p0) / k;
                p0 = p1;
                p1 = p2;
            }
            // Here p1 = P_n(x) and p0 = P_{n-1}(x) (also for n = 1).
            derivative = n * (x * p1 - p0) / (x * x - 1.0);
            const double step = p1 / derivative;
            x -= step;
            if (std::abs(step) < 1e-15) {
                break;
            }
        }
        const double w = 2.0 / ((1.0 - x * x) * derivative * derivative);
        nodes[size_t(i)] = {x, w};
        nodes[size_t(n - 1 - i)] = {-x, w};
    }
    return nodes;
}

} // namespace

SH9 projectSH9Uniform(std::span<const glm::vec3> directions, const RadianceFunction& radiance)
{
    if (directions.empty()) {
        throw InputError("SH projection needs at least one sample direction");
    }
    SumSH9 sum{};
    for (const glm::vec3& d : directions) {
        accumulate(sum, radiance(d), d, 1.0);
    }
    const double weight = 4.0 * kPi / double(directions.size());
    for (glm::dvec3& c : sum) {
        c *= weight;
    }
    return toSH9(sum);
}

SH9 projectCubeSH9King(const CubeMapF& cube)
{
    return projectCube(cube, texelSolidAngleKing);
}

SH9 projectCubeSH9BruteForce(const CubeMapF& cube)
{
    return projectCube(cube, texelSolidAngleExact);
}

SH9 projectSH9BruteForce(const RadianceFunction& radiance, int thetaSteps)
{
    if (thetaSteps < 1 || thetaSteps > kMaxThetaSteps) {
        throw InputError("brute-force SH needs 1 to " + std::to_string(kMaxThetaSteps) + " theta steps, got " +
                         std::to_string(thetaSteps));
    }
    const int phiSteps = 2 * thetaSteps;
    const double dPhi = 2.0 * kPi / phiSteps;
    SumSH9 sum{};
    for (const GaussNode& node : gaussLegendre(thetaSteps)) {
        const double cosTheta = node.x;
        const double sinTheta = std::sqrt(std::max(0.0, 1.0 - cosTheta * cosTheta));
        SumSH9 ring{};
        for (int j = 0; j < phiSteps; ++j) {
            const double phi = (j + 0.5) * dPhi;
            const glm::vec3 d(glm::dvec3(sinTheta * std::cos(phi), cosTheta, sinTheta * std::sin(phi)));
            accumulate(ring, radiance(d), d, 1.0);
        }
        for (size_t k = 0; k < 9; ++k) {
            sum[k] += ring[k] * (node.w * dPhi);
        }
    }
    return toSH9(sum);
}

glm::vec3 prefilterPhongBruteForce(const CubeMapF& cube, const glm::vec3& direction, float exponent)
{
    checkCubeMap(cube);
    const float length = glm::length(direction);
    if (!std::isfinite(length) || length == 0.0f) {
        throw InputError("Phong prefilter needs a finite non-zero direction");
    }
    if (!std::isfinite(exponent) || exponent < 0.0f) {
        throw InputError("Phong exponent must be finite and >= 0, got " + std::to_string(exponent));
    }
    const glm::dvec3 r = glm::dvec3(direction / length);
    // The lobe is evaluated relative to its largest texel value, (cos/cosMax)^n, so a huge
    // exponent cannot underflow every weight to zero; the ratio below is unchanged by it.
    double cosMax = 0.0;
    for (int f = 0; f < 6; ++f) {
        for (int y = 0; y < cube.size; ++y) {
            for (int x = 0; x < cube.size; ++x) {
                cosMax = std::max(cosMax, glm::dot(r, glm::dvec3(cubeTexelCentreDirection(f, cube.size, x, y))));
            }
        }
    }
    glm::dvec3 weightedSum(0.0);
    double lobeSum = 0.0;
    for (int f = 0; f < 6; ++f) {
        for (int y = 0; y < cube.size; ++y) {
            for (int x = 0; x < cube.size; ++x) {
                const double c = glm::dot(r, glm::dvec3(cubeTexelCentreDirection(f, cube.size, x, y)));
                if (c <= 0.0) {
                    continue;
                }
                const double w = std::pow(c / cosMax, double(exponent)) * texelSolidAngleExact(cube.size, x, y);
                weightedSum += glm::dvec3(texelValue(cube.faces[size_t(f)], x, y)) * w;
                lobeSum += w;
            }
        }
    }
    return glm::vec3(weightedSum / lobeSum);
}

double sh9RelativeError(const SH9& sh, const SH9& reference)
{
    double scale = 0.0, worst = 0.0;
    for (size_t k = 0; k < 9; ++k) {
        for (int c = 0; c < 3; ++c) {
            scale = std::max(scale, std::abs(double(reference[k][c])));
            worst = std::max(worst, std::abs(double(sh[k][c]) - double(reference[k][c])));
        }
    }
    if (scale == 0.0) {
        return worst == 0.0 ? 0.0 : std::numeric_limits<double>::infinity();
    }
    return worst / scale;
}

} // namespace lumar
