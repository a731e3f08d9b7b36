// The uniform direction sets of sphere_samples.h: counts, unit length, the first and second
// moments of a uniform distribution (mean 0, E[d dᵀ] = I/3), cap coverage and its mean
// cosine, determinism, and the pinned mt19937 → float derivation.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numbers>
#include <utility>
#include <vector>

#include <gtest/gtest.h>

#include "core/error.h"
#include "gles_renderer/ibl/sphere_samples.h"

namespace lumar {
namespace {

struct Moments {
    glm::dvec3 mean{0.0};
    glm::dmat3 second{0.0}; // (1/N) Σ d dᵀ
};

Moments moments(const std::vector<glm::vec3>& directions)
{
    Moments m;
    for (const glm::vec3& v : directions) {
        const glm::dvec3 d(v);
        m.mean += d;
        m.second += glm::outerProduct(d, d);
    }
    m.mean /= double(directions.size());
    m.second /= double(directions.size());
    return m;
}

double largestSecondMomentError(const Moments& m)
{
    double worst = 0.0;
    for (int i = 0; i < 3; ++i) {
        for (int j = 0; j < 3; ++j) {
            worst = std::max(worst, std::abs(m.second[i][j] - (i == j ? 1.0 / 3.0 : 0.0)));
        }
    }
    return worst;
}

void expectUnit(const std::vector<glm::vec3>& directions)
{
    for (const glm::vec3& d : directions) {
        ASSERT_NEAR(glm::length(d), 1.0f, 1e-6f);
    }
}

// Bounds scaled to N: independent uniform directions would give moment errors of order
// 1/√N; both sets do better (measured ≤ 0.17/√N at N = 64, falling faster after), so 0.5/√N
// is a loose bound that still catches a biased mapping (a wrong θ law moves E[y²] by ≥ 0.03).
TEST(SphereSamples, StratifiedSetHasTheMomentsOfTheUniformDistribution)
{
    for (const int side : {8, 32, 128}) {
        const std::vector<glm::vec3> directions = stratifiedSphereSamples(side, 11);
        ASSERT_EQ(directions.size(), size_t(side * side));
        expectUnit(directions);
        const Moments m = moments(directions);
        const double bound = 0.5 / side; // 0.5/√N
        EXPECT_LT(glm::length(m.mean), bound) << "side " << side;
        EXPECT_LT(largestSecondMomentError(m), bound) << "side " << side;
        std::printf("stratified N=%d: |mean| = %.2e, second moments off by %.2e (bound %.2e)\n", side * side,
                    glm::length(m.mean), largestSecondMomentError(m), bound);
    }
}

TEST(SphereSamples, FibonacciSetHasTheMomentsOfTheUniformDistribution)
{
    for (const int count : {64, 1000, 16384}) {
        const std::vector<glm::vec3> directions = fibonacciSphereSamples(count);
        ASSERT_EQ(directions.size(), size_t(count));
        expectUnit(directions);
        const Moments m = moments(directions);
        const double bound = 0.5 / std::sqrt(double(count));
        EXPECT_LT(glm::length(m.mean), bound) << "count " << count;
        EXPECT_LT(largestSecondMomentError(m), bound) << "count " << count;
        std::printf("Fibonacci N=%d: |mean| = %.2e, second moments off by %.2e (bound %.2e)\n", count,
                    glm::length(m.mean), largestSecondMomentError(m), bound);
    }
}

TEST(SphereSamples, FibonacciHeightsAreEvenlySpacedAboutY)
{
    const int count = 100;
    const std::vector<glm::vec3> directions = fibonacciSphereSamples(count);
    for (int k = 0; k < count; ++k) {
        EXPECT_NEAR(directions[size_t(k)].y, 1.0 - (2.0 * k + 1.0) / count, 1e-6) << "k = " << k;
    }
}

TEST(SphereSamples, StratifiedHeightsFillTheirCells)
{
    // Cell column i covers x ∈ [i, i+1)/n, so y = cosθ = 1 − 2x lies in [1 − 2(i+1)/n, 1 − 2i/n].
    const int side = 16;
    const std::vector<glm::vec3> directions = stratifiedSphereSamples(side, 3);
    for (int k = 0; k < side * side; ++k) {
        const int i = k % side;
        EXPECT_LE(directions[size_t(k)].y, 1.0f - 2.0f * float(i) / side + 1e-6f);
        EXPECT_GE(directions[size_t(k)].y, 1.0f - 2.0f * float(i + 1) / side - 1e-6f);
    }
}

TEST(SphereSamples, SameSeedSameDirectionsOtherSeedOtherDirections)
{
    const std::vector<glm::vec3> a = stratifiedSphereSamples(16, 42);
    const std::vector<glm::vec3> b = stratifiedSphereSamples(16, 42);
    const std::vector<glm::vec3> c = stratifiedSphereSamples(16, 43);
    EXPECT_EQ(a, b);
    EXPECT_NE(a, c);
    EXPECT_EQ(stratifiedCapSamples(8, 0.5f, 7), stratifiedCapSamples(8, 0.5f, 7));
}

TEST(SphereSamples, JitterComesFromTheRawMt19937Words)
{
    // The first two outputs of std::mt19937(1), fixed by the standard's algorithm, are
    // 1791095845 and 4282876139; the jitter is their top 24 bits over 2^24.
    const double x = double(1791095845u >> 8) / 16777216.0;
    const double y = double(4282876139u >> 8) / 16777216.0;
    const double cosTheta = 1.0 - 2.0 * x;
    const double sinTheta = std::sqrt(1.0 - cosTheta * cosTheta);
    const double phi = 2.0 * std::numbers::pi * y;
    const glm::vec3 d = stratifiedSphereSamples(1, 1).at(0);
    EXPECT_NEAR(d.x, sinTheta * std::cos(phi), 1e-6);
    EXPECT_NEAR(d.y, cosTheta, 1e-6);
    EXPECT_NEAR(d.z, sinTheta * std::sin(phi), 1e-6);
}

TEST(SphereSamples, CapSamplesStayInTheCapWithTheUniformMeanCosine)
{
    // Uniform in solid angle over the cap: cosθ is uniform in [cosMax, 1], mean (1 + cosMax)/2;
    // by symmetry the mean x and y vanish.
    for (const float cosMax : {-1.0f, 0.0f, 0.5f, 0.95f}) {
        const int side = 32;
        const std::vector<glm::vec3> directions = stratifiedCapSamples(side, cosMax, 5);
        ASSERT_EQ(directions.size(), size_t(side * side));
        expectUnit(directions);
        glm::dvec3 mean(0.0);
        for (const glm::vec3& d : directions) {
            EXPECT_GE(d.z, cosMax - 1e-6f);
            mean += glm::dvec3(d);
        }
        mean /= double(directions.size());
        const double height = 1.0 - cosMax;
        const double bound = height / side; // (1 − cosMax)/√N
        EXPECT_NEAR(mean.z, (1.0 + cosMax) / 2.0, bound) << "cosMax " << cosMax;
        EXPECT_NEAR(mean.x, 0.0, bound) << "cosMax " << cosMax;
        EXPECT_NEAR(mean.y, 0.0, bound) << "cosMax " << cosMax;
        EXPECT_NEAR(capSolidAngle(cosMax), 2.0 * std::numbers::pi * height, 1e-12);
    }
}

// The importance-sampled cap (glossy-2's prefilter samples): in the cap, the Fibonacci cap
// where m = 0, cosθ distributed as the density says (its mean), and Σ f/(N pdf) the cap
// integral of f, for f = 1 (the density is normalised) and f = cos^n (the lobe the
// prefilter integrates), at a prefilter's sample count.
TEST(SphereSamples, PowerCapSamplesFollowTheirDensity)
{
    const std::vector<glm::vec3> cap = fibonacciCapSamples(104, 0.9306f);
    const std::vector<glm::vec3> uniform = powerCapSamples(104, 0.0f, 0.9306f);
    ASSERT_EQ(uniform.size(), cap.size());
    for (size_t k = 0; k < cap.size(); ++k)
        EXPECT_LT(glm::length(uniform[k] - cap[k]), 1e-6f) << k;

    constexpr double kTwoPi = 2.0 * std::numbers::pi;
    for (const auto& [m, cosMax] : {std::pair(32.0, 0.9306), std::pair(16.0, 0.8), std::pair(4.0, 0.5)}) {
        const int count = 104;
        const std::vector<glm::vec3> directions = powerCapSamples(count, float(m), float(cosMax));
        ASSERT_EQ(directions.size(), size_t(count));
        expectUnit(directions);
        const double c0 = double(float(cosMax)); // the cap as powerCapSamples sees it
        double meanCos = 0.0, solidAngle = 0.0, lobe = 0.0;
        for (const glm::vec3& d : directions) {
            ASSERT_GE(d.z, float(c0) - 1e-6f);
            const double pdf = powerCapPdf(double(d.z), m, c0);
            ASSERT_GT(pdf, 0.0);
            meanCos += double(d.z) / count;
            solidAngle += 1.0 / (count * pdf);
            lobe += std::pow(double(d.z), 64.0) / (count * pdf);
        }
        // E[cosθ] = (m + 1)/(m + 2) (1 − c0^(m+2)) / (1 − c0^(m+1)) (measured within 1.1e-5);
        // a density one power off moves it by ≥ 3.2e-4, 10x the bound. The sums: within 0.0016.
        const double expectedCos =
            (m + 1.0) / (m + 2.0) * (1.0 - std::pow(c0, m + 2.0)) / (1.0 - std::pow(c0, m + 1.0));
        EXPECT_NEAR(meanCos, expectedCos, 3e-5) << "m " << m;
        EXPECT_NEAR(solidAngle / (kTwoPi * (1.0 - c0)), 1.0, 0.005) << "m " << m;
        const double exactLobe = kTwoPi * (1.0 - std::pow(c0, 65.0)) / 65.0;
        EXPECT_NEAR(lobe / exactLobe, 1.0, 0.005) << "m " << m;
    }
    EXPECT_EQ(powerCapPdf(0.5, 4.0, 0.6), 0.0); // outside the cap
}

TEST(SphereSamples, RejectsBadArguments)
{
    EXPECT_THROW(stratifiedSphereSamples(0, 1), InputError);
    EXPECT_THROW(stratifiedSphereSamples(4097, 1), InputError);
    EXPECT_THROW(fibonacciSphereSamples(0), InputError);
    EXPECT_THROW(fibonacciSphereSamples(-5), InputError);
    EXPECT_THROW(stratifiedCapSamples(0, 0.5f, 1), InputError);
    EXPECT_THROW(stratifiedCapSamples(8, 1.0f, 1), InputError);
    EXPECT_THROW(stratifiedCapSamples(8, -1.01f, 1), InputError);
    EXPECT_THROW(stratifiedCapSamples(8, std::numeric_limits<float>::quiet_NaN(), 1), InputError);
    EXPECT_NO_THROW(stratifiedCapSamples(1, -1.0f, 1));
    EXPECT_THROW(powerCapSamples(0, 4.0f, 0.5f), InputError);
    EXPECT_THROW(powerCapSamples(8, -1.0f, 0.5f), InputError);
    EXPECT_THROW(powerCapSamples(8, 4.0f, 1.0f), InputError);
    EXPECT_THROW(powerCapSamples(8, 4.0f, -0.1f), InputError);
    EXPECT_THROW(powerCapSamples(8, std::numeric_limits<float>::quiet_NaN(), 0.5f), InputError);
}

} // namespace
} // namespace lumar
