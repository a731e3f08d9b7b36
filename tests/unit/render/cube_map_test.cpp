// CPU cube maps against the OpenGL ES 3.0 face-selection table, written out by hand here,
// exact texel solid angles against 4π, King's approximation against the exact ones, and the
// lookups and resampling from an equirectangular map.
#include <cmath>
#include <numbers>
#include <vector>

#include <gtest/gtest.h>

#include "core/error.h"
#include "gles_renderer/ibl/cube_map.h"

namespace lumar {
namespace {

constexpr double kPi = std::numbers::pi;

TEST(CubeMap, CoordinateRoundTripsOnEveryFace)
{
    for (int face = 0; face < 6; ++face) {
        for (float s = 0.01f; s < 1.0f; s += 0.049f) {
            for (float t = 0.01f; t < 1.0f; t += 0.049f) {
                const glm::vec3 d = cubeTexelDirection(face, s, t);
                ASSERT_NEAR(glm::length(d), 1.0f, 1e-6f);
                const CubeCoord c = cubeCoordinate(d);
                ASSERT_EQ(c.face, face) << "s " << s << " t " << t;
                ASSERT_NEAR(c.s, s, 1e-6f);
                ASSERT_NEAR(c.t, t, 1e-6f);
            }
        }
    }
}

struct FaceCase {
    glm::vec3 dir;
    int face;
    float s, t;
};

TEST(CubeMap, FaceSelectionFollowsTheGlesTable)
{
    // ES 3.0 §3.8.10: +X sc=−rz tc=−ry; −X sc=rz tc=−ry; +Y sc=rx tc=rz; −Y sc=rx tc=−rz;
    // +Z sc=rx tc=−ry; −Z sc=−rx tc=−ry; s = (sc/|ma| + 1)/2, t = (tc/|ma| + 1)/2.
    const std::vector<FaceCase> cases = {
        {{1, 0, 0}, 0, 0.5f, 0.5f},
        {{-1, 0, 0}, 1, 0.5f, 0.5f},
        {{0, 1, 0}, 2, 0.5f, 0.5f},
        {{0, -1, 0}, 3, 0.5f, 0.5f},
        {{0, 0, 1}, 4, 0.5f, 0.5f},
        {{0, 0, -1}, 5, 0.5f, 0.5f},
        {{1, 0.5f, 0.25f}, 0, 0.375f, 0.25f},                 // sc = −0.25, tc = −0.5
        {{2, 1, 0.5f}, 0, 0.375f, 0.25f},                     // the same direction, |ma| = 2
        {{-1, 0.5f, 0.25f}, 1, 0.625f, 0.25f},                // sc = 0.25, tc = −0.5
        {{0.5f, 1, 0.25f}, 2, 0.75f, 0.625f},                 // sc = 0.5, tc = 0.25
        {{0.5f, -1, 0.25f}, 3, 0.75f, 0.375f},                // sc = 0.5, tc = −0.25
        {{0.5f, 0.25f, 1}, 4, 0.75f, 0.375f},                 // sc = 0.5, tc = −0.25
        {{0.5f, 0.25f, -1}, 5, 0.25f, 0.375f},                // sc = −0.5, tc = −0.25
        {{-0.2f, -0.9f, 0.6f}, 3, 7.0f / 18.0f, 1.0f / 6.0f}, // sc = −0.2/0.9, tc = −0.6/0.9
    };
    for (const FaceCase& c : cases) {
        const CubeCoord coord = cubeCoordinate(c.dir);
        EXPECT_EQ(coord.face, c.face) << c.dir.x << " " << c.dir.y << " " << c.dir.z;
        EXPECT_NEAR(coord.s, c.s, 1e-6f) << c.dir.x << " " << c.dir.y << " " << c.dir.z;
        EXPECT_NEAR(coord.t, c.t, 1e-6f) << c.dir.x << " " << c.dir.y << " " << c.dir.z;
    }
}

TEST(CubeMap, TexelRowZeroIsTNearZero)
{
    // On +X, t = 0 is tc = −1, i.e. ry = +1: the first uploaded row of +X looks up (+Y) and
    // its first column (s = 0, sc = −1) towards +Z.
    const CubeMapF cube = cubeFromFunction(4, [](glm::vec3 d) { return d; });
    const glm::vec3 firstTexel = cubeTexelCentreDirection(0, 4, 0, 0);
    EXPECT_GT(firstTexel.y, 0.5f);
    EXPECT_GT(firstTexel.z, 0.5f);
    EXPECT_EQ(sampleCubeNearest(cube, glm::vec3(1.0f, 0.9f, 0.9f)), firstTexel);
    const float* stored = cube.faces[0].at(0, 0);
    EXPECT_EQ(glm::vec3(stored[0], stored[1], stored[2]), firstTexel);
}

TEST(CubeMap, ExactTexelSolidAnglesSumTo4Pi)
{
    for (const int size : {1, 2, 7, 64, 256}) {
        double total = 0.0;
        for (int y = 0; y < size; ++y) {
            for (int x = 0; x < size; ++x) {
                total += texelSolidAngleExact(size, x, y);
            }
        }
        EXPECT_NEAR(6.0 * total, 4.0 * kPi, 1e-9) << "size " << size;
    }
    // One face texel of a 1-texel face is a sixth of the sphere; the centre texel of a 3×3
    // face is the square of half-width 1/3 seen from distance 1: 4·atan((1/9)/√(11/9)).
    EXPECT_NEAR(texelSolidAngleExact(1, 0, 0), 4.0 * kPi / 6.0, 1e-12);
    EXPECT_NEAR(texelSolidAngleExact(3, 1, 1), 4.0 * std::atan((1.0 / 9.0) / std::sqrt(11.0 / 9.0)), 1e-12);
}

TEST(CubeMap, KingWeightsOvershootTheExactOnesBySecondOrder)
{
    // Midpoint rule on dω = du dv / (1 + u² + v²)^{3/2}: the total is too large by a relative
    // c/size² (measured c = 0.245, i.e. 0.38 % at size 8), and per texel the worst ratio is at
    // the corners, also O(1/size²).
    for (const int size : {8, 16, 32, 64, 128}) {
        double king = 0.0, worstRatio = 0.0;
        for (int y = 0; y < size; ++y) {
            for (int x = 0; x < size; ++x) {
                king += texelSolidAngleKing(size, x, y);
                worstRatio = std::max(
                    worstRatio, std::abs(texelSolidAngleKing(size, x, y) / texelSolidAngleExact(size, x, y) - 1.0));
            }
        }
        const double excess = 6.0 * king / (4.0 * kPi) - 1.0;
        std::printf("size %3d: King total / 4pi - 1 = %.3e (x size^2 = %.4f), worst texel ratio - 1 = %.3e\n", size,
                    excess, excess * size * size, worstRatio);
        EXPECT_GT(excess, 0.0);
        EXPECT_NEAR(excess * size * size, 0.245, 0.005) << "size " << size;
        EXPECT_LT(worstRatio * size * size, 1.0) << "size " << size;
    }
}

TEST(CubeMap, BilinearIsExactForContentLinearInTexelsAndClampsAtEdges)
{
    // Face +Z holds (x, y, 0) at texel (x, y): bilinear at (s, t) gives the texel-space
    // position s·size − 0.5, clamped to [0, size − 1].
    const int size = 8;
    CubeMapF cube = cubeFromFunction(size, [](glm::vec3) { return glm::vec3(0.0f); });
    for (int y = 0; y < size; ++y) {
        for (int x = 0; x < size; ++x) {
            float* p = cube.faces[4].at(x, y);
            p[0] = float(x);
            p[1] = float(y);
        }
    }
    for (const float s : {0.02f, 0.3f, 0.5f, 0.77f, 0.99f}) {
        for (const float t : {0.01f, 0.41f, 0.93f}) {
            const glm::vec3 v = sampleCubeBilinear(cube, cubeTexelDirection(4, s, t));
            EXPECT_NEAR(v.x, std::clamp(s * size - 0.5f, 0.0f, size - 1.0f), 1e-4f) << s << " " << t;
            EXPECT_NEAR(v.y, std::clamp(t * size - 0.5f, 0.0f, size - 1.0f), 1e-4f) << s << " " << t;
        }
    }
}

TEST(CubeMap, CubeFromFunctionHoldsTheFunctionAtTexelCentres)
{
    const auto f = [](glm::vec3 d) { return glm::vec3(d.x, 2.0f * d.y, d.z * d.z); };
    const CubeMapF cube = cubeFromFunction(5, f);
    for (int face = 0; face < 6; ++face) {
        for (int y = 0; y < 5; ++y) {
            for (int x = 0; x < 5; ++x) {
                const float* p = cube.faces[size_t(face)].at(x, y);
                EXPECT_EQ(glm::vec3(p[0], p[1], p[2]), f(cubeTexelCentreDirection(face, 5, x, y)));
            }
        }
    }
}

TEST(CubeMap, EquirectLookupWrapsInLongitude)
{
    // Columns 0..3 hold 0..3. Towards −X (u = 0 = 1, the seam) the lookup falls halfway
    // between the last and the first column: (3 + 0)/2, not the clamped 0.
    ImageF equirect(4, 2, 3);
    for (int y = 0; y < 2; ++y) {
        for (int x = 0; x < 4; ++x) {
            float* p = equirect.at(x, y);
            p[0] = p[1] = p[2] = float(x);
        }
    }
    EXPECT_NEAR(sampleEquirectBilinear(equirect, glm::vec3(-1, 0, 0)).x, 1.5f, 1e-5f);
    // +X is u = 0.5: between columns 1 and 2.
    EXPECT_NEAR(sampleEquirectBilinear(equirect, glm::vec3(1, 0, 0)).x, 1.5f, 1e-5f);
    // u = 0.25 (−Z) is pixel position 0.5, halfway between columns 0 and 1.
    EXPECT_NEAR(sampleEquirectBilinear(equirect, glm::vec3(0, 0, -1)).x, 0.5f, 1e-5f);
}

TEST(CubeMap, CubeFromEquirectMatchesTheFunction)
{
    // A smooth function rendered into a 512×256 equirect (pixel centres, the convention of
    // environment_map.h) and resampled into a cube: bilinear interpolation error ~ h² f''/8
    // with h = 2π/512, well under 1e-3 for these second derivatives.
    const auto f = [](glm::vec3 d) { return glm::vec3(1.0f + 0.5f * d.x, 1.0f + 0.3f * d.y * d.z, 0.5f + d.z * d.z); };
    const int w = 512, h = 256;
    ImageF equirect(w, h, 3);
    for (int r = 0; r < h; ++r) {
        for (int c = 0; c < w; ++c) {
            const double theta = (r + 0.5) / h * kPi;
            const double phi = ((c + 0.5) / w - 0.5) * 2.0 * kPi;
            const glm::vec3 v =
                f(glm::vec3(std::sin(theta) * std::cos(phi), std::cos(theta), std::sin(theta) * std::sin(phi)));
            float* p = equirect.at(c, r);
            p[0] = v.x;
            p[1] = v.y;
            p[2] = v.z;
        }
    }
    const int size = 16;
    const CubeMapF cube = cubeFromEquirect(equirect, size);
    float worst = 0.0f;
    for (int face = 0; face < 6; ++face) {
        for (int y = 0; y < size; ++y) {
            for (int x = 0; x < size; ++x) {
                const float* p = cube.faces[size_t(face)].at(x, y);
                const glm::vec3 error =
                    glm::abs(glm::vec3(p[0], p[1], p[2]) - f(cubeTexelCentreDirection(face, size, x, y)));
                worst = std::max({worst, error.x, error.y, error.z});
            }
        }
    }
    std::printf("cube from equirect: worst texel error %.2e\n", worst);
    // Measured 7.3e-5. (No texel centre of a 16² cube falls in the half rows next to the poles,
    // where the lookup clamps instead of interpolating across the pole.)
    EXPECT_LT(worst, 2e-4f);
}

TEST(CubeMap, RejectsBadInput)
{
    EXPECT_THROW(cubeTexelDirection(6, 0.5f, 0.5f), InputError);
    EXPECT_THROW(cubeTexelDirection(-1, 0.5f, 0.5f), InputError);
    EXPECT_THROW(cubeCoordinate(glm::vec3(0.0f)), InputError);
    EXPECT_THROW(cubeCoordinate(glm::vec3(std::nanf(""), 1, 0)), InputError);
    EXPECT_THROW(cubeFromFunction(0, [](glm::vec3) { return glm::vec3(1.0f); }), InputError);
    EXPECT_THROW(cubeFromEquirect(ImageF(4, 2, 1), 4), InputError);
    EXPECT_THROW(cubeFromEquirect(ImageF(), 4), InputError);
    CubeMapF broken = cubeFromFunction(4, [](glm::vec3) { return glm::vec3(1.0f); });
    broken.faces[3] = ImageF(3, 4, 3);
    EXPECT_THROW(sampleCubeBilinear(broken, glm::vec3(0, 0, 1)), InputError);
    EXPECT_THROW(sampleEquirectBilinear(ImageF(4, 2, 3), glm::vec3(0.0f)), InputError);
}

} // namespace
} // namespace lumar
