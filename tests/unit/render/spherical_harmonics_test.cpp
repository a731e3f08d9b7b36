// SH9 basis, projection and irradiance against closed forms and against the float64
// reference of tests/data/env/sh9_reference.json (computed by a separate Python script).
#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <functional>
#include <numbers>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "gles_renderer/assets/environment_map.h"
#include "render_test_support.h"

namespace lumar {
namespace {

constexpr double kPi = std::numbers::pi;

// The direction convention of environment_map.h, written out again here.
glm::dvec3 pixelDirection(int row, int col, int width, int height)
{
    const double theta = (row + 0.5) / height * kPi;
    const double phi = ((col + 0.5) / width - 0.5) * 2.0 * kPi;
    return {std::sin(theta) * std::cos(phi), std::cos(theta), std::sin(theta) * std::sin(phi)};
}

ImageF environment(int width, int height, const std::function<glm::vec3(const glm::dvec3&)>& radiance)
{
    ImageF image(width, height, 3);
    for (int r = 0; r < height; ++r) {
        for (int c = 0; c < width; ++c) {
            const glm::vec3 value = radiance(pixelDirection(r, c, width, height));
            float* p = image.at(c, r);
            p[0] = value.x;
            p[1] = value.y;
            p[2] = value.z;
        }
    }
    return image;
}

// The formulas of sh9_reference.json's "_sh_basis", written out again (x, y, z of d).
std::array<double, 9> referenceBasis(const glm::dvec3& d)
{
    return {0.282095,
            0.488603 * d.y,
            0.488603 * d.z,
            0.488603 * d.x,
            1.092548 * d.x * d.y,
            1.092548 * d.y * d.z,
            0.315392 * (3 * d.z * d.z - 1),
            1.092548 * d.x * d.z,
            0.546274 * (d.x * d.x - d.y * d.y)};
}

TEST(SphericalHarmonics, BasisFollowsTheReferenceOrderAndSigns)
{
    std::mt19937 random(7);
    std::normal_distribution<double> gauss;
    for (int i = 0; i < 200; ++i) {
        const glm::dvec3 d = glm::normalize(glm::dvec3(gauss(random), gauss(random), gauss(random)));
        const std::array<float, 9> ours = shBasis(glm::vec3(d));
        const std::array<double, 9> expected = referenceBasis(d);
        for (size_t k = 0; k < 9; ++k) {
            EXPECT_NEAR(ours[k], expected[k], 1e-6) << "k = " << k;
        }
    }
}

// Equirect resolution for the analytic tests: the midpoint rule in theta with exact row
// solid angles has an error of order (pi / H)^2 / 24 ~ 3e-5 at H = 128.
constexpr int kWidth = 256;
constexpr int kHeight = 128;

TEST(SphericalHarmonics, BasisIsOrthonormalUnderTheProjection)
{
    // Projecting Y_j gives the j-th row of the Gram matrix: delta_ij to within 1e-3.
    for (size_t j = 0; j < 9; ++j) {
        const ImageF image = environment(
            kWidth, kHeight, [&](const glm::dvec3& d) { return glm::vec3(float(referenceBasis(d)[j]), 0.0f, 0.0f); });
        const SH9 sh = projectEquirectSH9(image);
        for (size_t i = 0; i < 9; ++i) {
            EXPECT_NEAR(sh[i].x, i == j ? 1.0 : 0.0, 1e-3) << "i = " << i << ", j = " << j;
        }
    }
}

void expectCoefficients(const SH9& sh, const std::array<glm::dvec3, 9>& expected, double relativeTolerance)
{
    double scale = 0.0;
    for (const glm::dvec3& e : expected) {
        scale = std::max({scale, std::abs(e.x), std::abs(e.y), std::abs(e.z)});
    }
    for (size_t k = 0; k < 9; ++k) {
        for (int c = 0; c < 3; ++c) {
            EXPECT_NEAR(sh[k][c], expected[k][c], relativeTolerance * scale) << "k = " << k << ", channel " << c;
        }
    }
}

TEST(SphericalHarmonics, ConstantEnvironment)
{
    // L = c: c_0 = c * 0.282095 * 4 pi, every other coefficient integrates to zero.
    const glm::dvec3 c(1.0, 2.0, 0.5);
    const SH9 sh = projectEquirectSH9(environment(kWidth, kHeight, [&](const glm::dvec3&) { return glm::vec3(c); }));
    std::array<glm::dvec3, 9> expected{};
    expected[0] = c * 0.282095 * 4.0 * kPi;
    expectCoefficients(sh, expected, 1e-4);
}

TEST(SphericalHarmonics, LinearEnvironment)
{
    // L = a + b y: c_0 = a * 0.282095 * 4 pi, c_1 (the y term) = b * 0.488603 * 4 pi / 3.
    const glm::dvec3 a(1.0, 0.5, 2.0);
    const glm::dvec3 b(0.5, -1.0, 0.25);
    const SH9 sh =
        projectEquirectSH9(environment(kWidth, kHeight, [&](const glm::dvec3& d) { return glm::vec3(a + b * d.y); }));
    std::array<glm::dvec3, 9> expected{};
    expected[0] = a * 0.282095 * 4.0 * kPi;
    expected[1] = b * 0.488603 * 4.0 * kPi / 3.0;
    expectCoefficients(sh, expected, 1e-4);
}

TEST(SphericalHarmonics, ClampedCosineLobeAboutUp)
{
    // L = max(0, y). Over the upper hemisphere: int y = pi, int y^2 = 2 pi / 3,
    // int y^3 = pi / 2, int y x^2 = int y z^2 = pi / 4; odd terms in x or z vanish. So
    // c_0 = 0.282095 pi, c_1 = 0.488603 * 2 pi / 3, c_6 = 0.315392 (3 pi/4 - pi),
    // c_8 = 0.546274 (pi/4 - pi/2). H is even, so the kink at the horizon lies on a row edge.
    const SH9 sh = projectEquirectSH9(
        environment(kWidth, kHeight, [](const glm::dvec3& d) { return glm::vec3(float(std::max(0.0, d.y))); }));
    std::array<glm::dvec3, 9> expected{};
    expected[0] = glm::dvec3(0.282095 * kPi);
    expected[1] = glm::dvec3(0.488603 * 2.0 * kPi / 3.0);
    expected[6] = glm::dvec3(-0.315392 * kPi / 4.0);
    expected[8] = glm::dvec3(-0.546274 * kPi / 4.0);
    expectCoefficients(sh, expected, 1e-4);
}

TEST(SphericalHarmonics, IrradianceOfAConstantEnvironmentIsPi)
{
    // The band-2 terms of a constant integrate to O((pi / H)^2) instead of 0, which moves E
    // by ~1e-4 at H = 128 and ~2.5e-5 at H = 256, used here.
    const SH9 sh = projectEquirectSH9(environment(512, 256, [](const glm::dvec3&) { return glm::vec3(1.0f); }));
    std::mt19937 random(3);
    std::normal_distribution<float> gauss;
    for (int i = 0; i < 100; ++i) {
        const glm::vec3 n = glm::normalize(glm::vec3(gauss(random), gauss(random), gauss(random)));
        const glm::vec3 e = irradianceSH9(sh, n);
        for (int c = 0; c < 3; ++c) {
            EXPECT_NEAR(e[c], kPi, 1e-4);
        }
    }
}

TEST(SphericalHarmonics, IrradianceOfALinearEnvironmentIsExact)
{
    // E(n) = int (a + b w.y) max(0, n.w) dw = pi a + (2 pi / 3) b n.y, which bands 0 and 1
    // hold exactly: the nine-coefficient formula must reproduce it (to the projection error).
    const double a = 1.5, b = 0.75;
    const SH9 sh = projectEquirectSH9(
        environment(kWidth, kHeight, [&](const glm::dvec3& d) { return glm::vec3(float(a + b * d.y)); }));
    std::mt19937 random(5);
    std::normal_distribution<float> gauss;
    for (int i = 0; i < 100; ++i) {
        const glm::vec3 n = glm::normalize(glm::vec3(gauss(random), gauss(random), gauss(random)));
        const double expected = kPi * a + 2.0 * kPi / 3.0 * b * n.y;
        EXPECT_NEAR(irradianceSH9(sh, n).x, expected, 1e-3 * kPi * a);
    }
}

// sh9_reference.json's maps.<map>.sh9_rgb: 9 rows of 3 numbers. A minimal reader for this
// one known file (no JSON library in the project's dependencies).
std::vector<double> referenceCoefficients(const std::string& map)
{
    std::ifstream in(test::testDataPath("env/sh9_reference.json"));
    std::stringstream text;
    text << in.rdbuf();
    const std::string json = text.str();
    size_t at = json.find("\"" + map + "\"");
    at = json.find("\"sh9_rgb\"", at);
    at = json.find('[', at);
    if (at == std::string::npos) {
        return {};
    }
    std::vector<double> values;
    int depth = 0;
    for (size_t i = at; i < json.size(); ++i) {
        const char ch = json[i];
        if (ch == '[') {
            ++depth;
        } else if (ch == ']') {
            if (--depth == 0) {
                break;
            }
        } else if (ch == '-' || (ch >= '0' && ch <= '9')) {
            char* end = nullptr;
            values.push_back(std::strtod(json.c_str() + i, &end));
            i = size_t(end - json.c_str()) - 1;
        }
    }
    return values;
}

TEST(SphericalHarmonics, VeniceSunsetMatchesTheFloat64Reference)
{
    const std::vector<double> reference = referenceCoefficients("venice_sunset_1k.hdr");
    ASSERT_EQ(reference.size(), 27u);
    const SH9 sh = projectEquirectSH9(loadHdrImage(test::sourcePath("daemon/assets/env/venice_sunset_1k.hdr")));
    for (int c = 0; c < 3; ++c) {
        double largest = 0.0;
        for (size_t k = 0; k < 9; ++k) {
            largest = std::max(largest, std::abs(reference[k * 3 + size_t(c)]));
        }
        double worst = 0.0;
        for (size_t k = 0; k < 9; ++k) {
            const double error = std::abs(sh[k][c] - reference[k * 3 + size_t(c)]) / largest;
            worst = std::max(worst, error);
            EXPECT_LE(error, 0.005) << "k = " << k << ", channel " << c << ": " << sh[k][c] << " vs "
                                    << reference[k * 3 + size_t(c)];
        }
        RecordProperty("worst_relative_error_channel_" + std::to_string(c), std::to_string(worst));
        std::printf("channel %d: worst |error| / largest |coefficient| = %.2e\n", c, worst);
    }
}

} // namespace
} // namespace lumar
