// Models land where the pinhole model says: a point X_cam of a model appears on pixel
// intrinsics.project(X_cam) (pixel centres at integer coordinates).
#include <cmath>

#include <glm/gtc/matrix_transform.hpp>
#include <gtest/gtest.h>

#include "gl_test_support.h"

namespace lumar {
namespace {

constexpr int kWidth = 320;
constexpr int kHeight = 240;

// Pixels whose colour differs from the (black) background.
bool covered(const Image8& image, int x, int y)
{
    const uint8_t* p = image.at(x, y);
    return p[0] > 0 || p[1] > 0 || p[2] > 0;
}

// Setup shared by the tests: black background, black environment, an emissive model.
struct Scene {
    SceneRenderer& renderer;
    Image8 background = test::solidImage(kWidth, kHeight, 0, 0, 0);
    explicit Scene(SceneRenderer& r) : renderer(r) { renderer.setEnvironment(test::uniformEnvironment(0.0f), 1.0f); }
    Image8 draw(const GltfModel& model, const glm::dmat4& cameraFromModel, const CameraIntrinsics& k)
    {
        renderer.removeModels();
        const DrawItem item{renderer.addModel(model), cameraFromModel};
        Image8 out;
        renderer.render(background, k, {&item, 1});
        renderer.readback(out);
        return out;
    }
};

// A fronto-parallel rectangle whose edges project to known fractional pixel positions
// covers exactly the pixel centres inside it: exact to the pixel, with every edge 0.2 px
// or more from the nearest centre (an error of 0.2 px or more in any edge fails it).
TEST(Projection, RectangleCoversExactlyThePixelCentresInsideItsProjection)
{
    LUMAR_RENDERER_OR_SKIP(renderer, kWidth, kHeight);
    Scene scene(renderer);
    // Unequal focal lengths and an off-centre principal point catch swapped or dropped terms.
    const CameraIntrinsics k = test::makeIntrinsics(kWidth, kHeight, 300.0, 280.0, 157.3, 118.6);
    const double z = 2.0;
    const double u0 = 100.3, u1 = 220.7, v0 = 50.2, v1 = 180.6;
    const glm::dvec3 offset(0.05, -0.03, z); // cameraFromModel translation
    const auto xAt = [&](double u) { return float((u - k.cx) * z / k.fx - offset.x); };
    const auto yAt = [&](double v) { return float((v - k.cy) * z / k.fy - offset.y); };
    const Image8 out =
        scene.draw(test::cameraFacingRectangle(xAt(u0), yAt(v0), xAt(u1), yAt(v1), test::emissiveMaterial({1, 1, 1})),
                   test::translation(offset.x, offset.y, offset.z), k);
    int wrong = 0;
    for (int y = 0; y < kHeight; ++y)
        for (int x = 0; x < kWidth; ++x) {
            const bool inside = x > u0 && x < u1 && y > v0 && y < v1;
            if (covered(out, x, y) != inside && ++wrong <= 5)
                ADD_FAILURE() << "pixel (" << x << ", " << y << ") " << (inside ? "not covered" : "covered");
        }
    EXPECT_EQ(wrong, 0);
}

// A tilted, rotated quad: the centroid of its covered pixel centres matches the centroid of
// the polygon of its projected corners within 0.1 px, and its area within 1%.
TEST(Projection, TiltedQuadCentroidMatchesThePinholeProjection)
{
    LUMAR_RENDERER_OR_SKIP(renderer, kWidth, kHeight);
    Scene scene(renderer);
    const CameraIntrinsics k = test::makeIntrinsics(kWidth, kHeight, 260.0, 250.0, 170.2, 112.9);
    const GltfModel quad = test::cameraFacingRectangle(-0.15f, -0.1f, 0.2f, 0.12f, test::emissiveMaterial({1, 1, 1}));
    glm::dmat4 cameraFromModel = test::translation(0.08, -0.05, 1.3);
    cameraFromModel = glm::rotate(cameraFromModel, glm::radians(35.0), glm::normalize(glm::dvec3(0.3, 1.0, 0.2)));
    cameraFromModel = glm::rotate(cameraFromModel, glm::radians(20.0), glm::dvec3(0, 0, 1));
    const Image8 out = scene.draw(quad, cameraFromModel, k);

    // Expected: shoelace area and centroid of the projected corners.
    glm::dvec2 corners[4];
    for (int i = 0; i < 4; ++i)
        corners[i] = k.project(
            glm::dvec3(cameraFromModel * glm::dvec4(glm::dvec3(quad.primitives[0].positions[size_t(i)]), 1.0)));
    double area = 0;
    glm::dvec2 centroid(0.0);
    for (int i = 0; i < 4; ++i) {
        const glm::dvec2 a = corners[i], b = corners[(i + 1) % 4];
        const double cross = a.x * b.y - b.x * a.y;
        area += cross;
        centroid += (a + b) * cross;
    }
    area *= 0.5;
    centroid /= 6.0 * area;
    area = std::abs(area);

    double count = 0;
    glm::dvec2 sum(0.0);
    for (int y = 0; y < kHeight; ++y)
        for (int x = 0; x < kWidth; ++x)
            if (covered(out, x, y)) {
                count += 1;
                sum += glm::dvec2(x, y);
            }
    ASSERT_GT(count, 1000.0);
    EXPECT_NEAR(count, area, 0.01 * area);
    EXPECT_NEAR(sum.x / count, centroid.x, 0.1);
    EXPECT_NEAR(sum.y / count, centroid.y, 0.1);
}

// glTF's front faces are counter-clockwise; back faces are culled unless double-sided, and a
// mirroring transform keeps the faces that face the camera.
TEST(Projection, BackFacesAreCulledUnlessDoubleSidedAndMirroringKeepsFrontFaces)
{
    LUMAR_RENDERER_OR_SKIP(renderer, kWidth, kHeight);
    Scene scene(renderer);
    const CameraIntrinsics k = test::makeIntrinsics(kWidth, kHeight, 250, 250, 159.5, 119.5);
    const GltfMaterial singleSided = test::emissiveMaterial({1, 1, 1});
    GltfMaterial doubleSided = singleSided;
    doubleSided.doubleSided = true;
    const glm::dmat4 ahead = test::translation(0, 0, 1);
    const glm::dmat4 turned = glm::rotate(ahead, glm::radians(180.0), glm::dvec3(0, 1, 0));
    const glm::dmat4 mirrored = glm::scale(ahead, glm::dvec3(-1, 1, 1));

    EXPECT_TRUE(
        covered(scene.draw(test::cameraFacingRectangle(-0.1f, -0.1f, 0.1f, 0.1f, singleSided), ahead, k), 160, 120));
    EXPECT_FALSE(
        covered(scene.draw(test::cameraFacingRectangle(-0.1f, -0.1f, 0.1f, 0.1f, singleSided), turned, k), 160, 120));
    EXPECT_TRUE(
        covered(scene.draw(test::cameraFacingRectangle(-0.1f, -0.1f, 0.1f, 0.1f, doubleSided), turned, k), 160, 120));
    EXPECT_TRUE(
        covered(scene.draw(test::cameraFacingRectangle(-0.1f, -0.1f, 0.1f, 0.1f, singleSided), mirrored, k), 160, 120));
}

// Geometry behind the near plane (0.01 m) or beyond the far plane (100 m) is clipped.
TEST(Projection, ClipsAtTheNearAndFarPlanes)
{
    LUMAR_RENDERER_OR_SKIP(renderer, kWidth, kHeight);
    Scene scene(renderer);
    const CameraIntrinsics k = test::makeIntrinsics(kWidth, kHeight, 250, 250, 159.5, 119.5);
    const GltfModel quad =
        test::cameraFacingRectangle(-0.001f, -0.001f, 0.001f, 0.001f, test::emissiveMaterial({1, 1, 1}));
    EXPECT_TRUE(covered(scene.draw(quad, test::translation(0, 0, 0.011), k), 160, 120));
    EXPECT_FALSE(covered(scene.draw(quad, test::translation(0, 0, 0.009), k), 160, 120));
    const GltfModel big = test::cameraFacingRectangle(-10, -10, 10, 10, test::emissiveMaterial({1, 1, 1}));
    EXPECT_TRUE(covered(scene.draw(big, test::translation(0, 0, 99), k), 160, 120));
    EXPECT_FALSE(covered(scene.draw(big, test::translation(0, 0, 101), k), 160, 120));
}

} // namespace
} // namespace lumar
