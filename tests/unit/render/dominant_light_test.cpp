// The dominant light extracted from an environment's SH (gles_renderer/ibl/dominant_light.h):
// on an analytic sky (one small bright disc over a dim constant) it finds the disc's direction
// and its irradiance; on the shipped venice_sunset_1k.hdr it points at the sun.
#include <cmath>
#include <numbers>

#include <gtest/gtest.h>

#include "gles_renderer/assets/environment_map.h"
#include "gles_renderer/ibl/dominant_light.h"
#include "render_test_support.h"

namespace lumar {
namespace {

constexpr double kPi = std::numbers::pi;

double degreesBetween(const glm::dvec3& a, const glm::dvec3& b)
{
    return std::acos(std::clamp(glm::dot(glm::normalize(a), glm::normalize(b)), -1.0, 1.0)) * 180.0 / kPi;
}

// Direction of pixel centre (x, y) of a width x height equirect (environment_map.h).
glm::dvec3 pixelDirection(int x, int y, int width, int height)
{
    const double theta = (y + 0.5) / height * kPi;
    const double phi = ((x + 0.5) / width - 0.5) * 2.0 * kPi;
    return {std::sin(theta) * std::cos(phi), std::cos(theta), std::sin(theta) * std::sin(phi)};
}

glm::dvec3 fromElevationAzimuth(double elevationDeg, double azimuthDeg)
{
    const double e = elevationDeg * kPi / 180.0, a = azimuthDeg * kPi / 180.0;
    return {std::cos(e) * std::cos(a), std::sin(e), std::cos(e) * std::sin(a)};
}

TEST(DominantLight, FindsASmallBrightDiscOnADimConstantSky)
{
    constexpr int kWidth = 512, kHeight = 256;
    const glm::dvec3 sun = fromElevationAzimuth(40.0, 120.0);
    const glm::dvec3 colour(6.0, 4.0, 2.0); // the disc's radiance
    const double ambient = 0.2;
    const double discRadius = 3.0 * kPi / 180.0;
    ImageF sky(kWidth, kHeight, 3);
    // The disc's irradiance at normal incidence as the image holds it: its pixels' solid
    // angles (the same weights projectEquirectSH9 uses) times its radiance.
    glm::dvec3 irradiance(0.0);
    for (int y = 0; y < kHeight; ++y) {
        const double solidAngle =
            (std::cos(y * kPi / kHeight) - std::cos((y + 1) * kPi / kHeight)) * 2.0 * kPi / kWidth;
        for (int x = 0; x < kWidth; ++x) {
            const bool inDisc = glm::dot(pixelDirection(x, y, kWidth, kHeight), sun) > std::cos(discRadius);
            for (int c = 0; c < 3; ++c)
                sky.at(x, y)[c] = float(ambient + (inDisc ? colour[c] : 0.0));
            if (inDisc)
                irradiance += colour * solidAngle;
        }
    }
    const DominantLight light = dominantLight(sky);
    // Stated bounds: direction within 1 degree, colour within 3 % per channel (the disc is
    // 3 degrees wide and drawn on a grid of 0.7-degree pixels).
    EXPECT_LT(degreesBetween(glm::dvec3(light.direction), sun), 1.0);
    EXPECT_NEAR(glm::length(glm::dvec3(light.direction)), 1.0, 1e-5);
    for (int c = 0; c < 3; ++c)
        EXPECT_NEAR(light.color[c], irradiance[c], 0.03 * irradiance[c]) << "channel " << c;
}

TEST(DominantLight, AConstantSkyHasNone)
{
    ImageF sky(64, 32, 3);
    std::fill(sky.data.begin(), sky.data.end(), 1.0f);
    const DominantLight light = dominantLight(sky);
    for (int c = 0; c < 3; ++c)
        EXPECT_LT(light.color[c], 1e-3f);
}

TEST(DominantLight, PointsAtTheSunOfVeniceSunset)
{
    const ImageF venice = loadHdrImage(test::sourcePath("daemon/assets/env/venice_sunset_1k.hdr"));
    // The brightest texel (by luminance): the sun.
    int bestX = 0, bestY = 0;
    double best = -1.0;
    for (int y = 0; y < venice.height; ++y)
        for (int x = 0; x < venice.width; ++x) {
            const float* p = venice.at(x, y);
            const double luminance = 0.2126 * p[0] + 0.7152 * p[1] + 0.0722 * p[2];
            if (luminance > best) {
                best = luminance;
                bestX = x;
                bestY = y;
            }
        }
    const glm::dvec3 sun = pixelDirection(bestX, bestY, venice.width, venice.height);
    const DominantLight light = dominantLight(venice);
    const glm::dvec3 d(light.direction);
    const double elevationDeg = std::asin(d.y) * 180.0 / kPi;
    const double azimuthDeg = std::atan2(d.z, d.x) * 180.0 / kPi;
    const double sunAzimuthDeg = std::atan2(sun.z, sun.x) * 180.0 / kPi;
    double azimuthError = std::abs(azimuthDeg - sunAzimuthDeg);
    azimuthError = std::min(azimuthError, 360.0 - azimuthError);
    std::printf("venice: light elevation %.1f deg, azimuth %.1f deg (sun texel: elevation %.1f, azimuth %.1f), "
                "colour %.3f %.3f %.3f\n",
                elevationDeg, azimuthDeg, std::asin(sun.y) * 180.0 / kPi, sunAzimuthDeg, light.color.r, light.color.g,
                light.color.b);
    const SH9 sh = projectEquirectSH9(venice);
    const glm::vec3 facing = irradianceSH9(sh, light.direction), up = irradianceSH9(sh, glm::vec3(0, 1, 0));
    std::printf("venice: irradiance facing the light %.3f %.3f %.3f, facing up %.3f %.3f %.3f\n", facing.r, facing.g,
                facing.b, up.r, up.g, up.b);
    EXPECT_GT(elevationDeg, 0.0);
    EXPECT_LT(azimuthError, 20.0);
    EXPECT_GT(light.color.r, 0.0f);
}

} // namespace
} // namespace lumar
