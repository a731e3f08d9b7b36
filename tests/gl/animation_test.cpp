// Animation that plays (issue 20): a generated skinned bar (tests/unit/render/animated_gltf.h)
// rendered at several times of its clip moves by what the rig says — its silhouette's extent
// measured in the image against the projection of the posed corners — and its posed shape
// is what its shadow and environment map see.
#include <algorithm>
#include <cmath>
#include <vector>

#include <gtest/gtest.h>

#include "gl_test_support.h"
#include "gles_renderer/assets/gltf_model.h"
#include "unit/render/animated_gltf.h"

namespace lumar {
namespace {

constexpr int kSize = 200;
constexpr double kFocal = 200.0, kCentre = 99.5;
constexpr double kDistance = 5.0;

// The camera kDistance in front of the bar (+z), looking at the knee (0, 1, 0): model x to the
// image's right, model y up (image y down).
glm::dmat4 cameraFromModel()
{
    glm::dmat4 m(1.0);
    m[1][1] = -1.0;
    m[2][2] = -1.0;
    m[3] = glm::dvec4(0.0, 1.0, kDistance, 1.0);
    return m;
}

glm::dvec2 pixelOf(const glm::dvec3& model)
{
    const glm::dvec3 c(cameraFromModel() * glm::dvec4(model, 1.0));
    return {kCentre + kFocal * c.x / c.z, kCentre + kFocal * c.y / c.z};
}

struct Extent {
    double left = 1e9, right = -1e9, top = 1e9, bottom = -1e9; // pixel edges
    int pixels = 0;
};

// The bar's pixels: it glows white over a black camera image.
Extent objectExtent(const Image8& image)
{
    Extent e;
    for (int y = 0; y < image.height; ++y)
        for (int x = 0; x < image.width; ++x)
            if (image.at(x, y)[1] > 128) {
                e.left = std::min(e.left, double(x));
                e.right = std::max(e.right, double(x + 1));
                e.top = std::min(e.top, double(y));
                e.bottom = std::max(e.bottom, double(y + 1));
                ++e.pixels;
            }
    return e;
}

Image8 renderAt(SceneRenderer& renderer, ModelId model, double seconds)
{
    const ClipTime clip[] = {{0, seconds}};
    renderer.poseModel(model, clip);
    const DrawItem item{model, cameraFromModel(), 0};
    renderer.render(test::solidImage(kSize, kSize, 0, 0, 0),
                    test::makeIntrinsics(kSize, kSize, kFocal, kFocal, kCentre, kCentre), std::span(&item, 1));
    Image8 out;
    renderer.readback(out);
    return out;
}

// The extent the posed corners project to (the bar is a flat strip facing the camera).
Extent expectedExtent(const std::vector<glm::dvec3>& corners)
{
    Extent e;
    for (const glm::dvec3& c : corners) {
        const glm::dvec2 p = pixelOf(c) + glm::dvec2(0.5); // pixel centres to edges
        e.left = std::min(e.left, p.x);
        e.right = std::max(e.right, p.x);
        e.top = std::min(e.top, p.y);
        e.bottom = std::max(e.bottom, p.y);
    }
    return e;
}

void expectExtent(const Extent& actual, const Extent& expected, const char* when)
{
    // Rasterisation covers a pixel whose centre lies inside: edges within a pixel.
    EXPECT_NEAR(actual.left, expected.left, 1.0) << when;
    EXPECT_NEAR(actual.right, expected.right, 1.0) << when;
    EXPECT_NEAR(actual.top, expected.top, 1.0) << when;
    EXPECT_NEAR(actual.bottom, expected.bottom, 1.0) << when;
}

TEST(Animation, SkinnedBarMovesByWhatItsRigSays)
{
    LUMAR_RENDERER_OR_SKIP(renderer, kSize, kSize);
    renderer.setEnvironment(test::uniformEnvironment(0.0f), 1.0f);
    test::ScratchDir dir;
    GltfModel model = loadGltfModel(test::bendingBar().write(dir, "bar"));
    model.materials.assign(1, test::emissiveMaterial(glm::vec3(1.0f)));
    model.materials[0].doubleSided = true;
    const ModelId id = renderer.addModel(model);

    // At rest: the bar stands from y = 0 to 2.
    const Extent rest = objectExtent(renderAt(renderer, id, 0.0));
    expectExtent(rest, expectedExtent({{-0.1, 0, 0}, {0.1, 2, 0}}), "at 0 s");
    // At 1 s the knee has turned 90 degrees: the top half lies along -x at y = 1.
    const Extent bent = objectExtent(renderAt(renderer, id, 1.0));
    expectExtent(bent, expectedExtent({{-1, 0.9, 0}, {-1, 1.1, 0}, {0.1, 0, 0}, {0.1, 1, 0}}), "at 1 s");
    // The top moved down by one model unit and out by 0.9: kFocal / kDistance pixels a unit.
    EXPECT_NEAR(bent.top - rest.top, (2.0 - 1.1) * kFocal / kDistance, 1.5);
    EXPECT_NEAR(rest.left - bent.left, 0.9 * kFocal / kDistance, 1.5);
    // At 0.5 s, 45 degrees (slerp): the top corners at the knee + R(45) (+-0.1, 1).
    const double s = std::sqrt(0.5);
    const auto turned = [&](double x, double y) { return glm::dvec3(s * x - s * y, 1.0 + s * x + s * y, 0.0); };
    const Extent half = objectExtent(renderAt(renderer, id, 0.5));
    expectExtent(
        half, expectedExtent({turned(-0.1, 1), turned(0.1, 1), {-0.1, 1, 0}, {0.1, 1, 0}, {0.1, 0, 0}, {-0.1, 0, 0}}),
        "at 0.5 s");
    // Back to the start: the same image as the first.
    const Extent again = objectExtent(renderAt(renderer, id, 0.0));
    EXPECT_EQ(again.pixels, rest.pixels);
    EXPECT_EQ(again.left, rest.left);
}

TEST(Animation, PoseModelRejectsWhatTheModelDoesNotHave)
{
    LUMAR_RENDERER_OR_SKIP(renderer, 16, 16);
    const ModelId still = renderer.addModel(test::cameraFacingRectangle(0, 0, 1, 1, GltfMaterial{}));
    renderer.poseModel(still, {}); // nothing to do
    const ClipTime clip[] = {{0, 0.0}};
    EXPECT_THROW(renderer.poseModel(still, clip), InputError);
    EXPECT_THROW(renderer.poseModel(7, clip), InputError);
    test::ScratchDir dir;
    const ModelId bar = renderer.addModel(loadGltfModel(test::bendingBar().write(dir, "bar")));
    const ClipTime missing[] = {{3, 0.0}};
    EXPECT_THROW(renderer.poseModel(bar, missing), InputError);
}

} // namespace
} // namespace lumar
