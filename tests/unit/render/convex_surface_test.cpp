#include <glm/gtc/matrix_transform.hpp>
#include <gtest/gtest.h>

#include "gles_renderer/assets/builtin_shapes.h"
#include "gles_renderer/assets/convex_surface.h"

namespace lumar {
namespace {

TEST(ConvexSurface, TheBuiltinPhantomShapesAreConvex)
{
    EXPECT_TRUE(isConvexSurface(makeCube()));
    EXPECT_TRUE(isConvexSurface(makePlane()));
    EXPECT_TRUE(isConvexSurface(makeCylinder()));
}

TEST(ConvexSurface, TwoBoxesApartAreNot)
{
    GltfModel model = makeCube();
    GltfPrimitive second = model.primitives.front();
    second.modelFromMesh = glm::translate(glm::mat4(1.0f), glm::vec3(3.0f, 0.0f, 0.0f));
    model.primitives.push_back(second);
    EXPECT_FALSE(isConvexSurface(model));
}

TEST(ConvexSurface, AnInwardWindingIsNotButAMirrorOfAnOutwardOneIs)
{
    GltfModel inward = makeCube();
    for (GltfPrimitive& primitive : inward.primitives)
        for (size_t t = 0; t + 2 < primitive.indices.size(); t += 3)
            std::swap(primitive.indices[t + 1], primitive.indices[t + 2]);
    EXPECT_FALSE(isConvexSurface(inward));

    // Mirrored, the renderer turns the front face round: still outward.
    GltfModel mirrored = makeCube();
    for (GltfPrimitive& primitive : mirrored.primitives)
        primitive.modelFromMesh = glm::scale(glm::mat4(1.0f), glm::vec3(-1.0f, 1.0f, 1.0f));
    EXPECT_TRUE(isConvexSurface(mirrored));
}

TEST(ConvexSurface, EmptyBrokenOrTooFineModelsAreNot)
{
    EXPECT_FALSE(isConvexSurface(GltfModel{}));
    GltfModel broken = makeCube();
    broken.primitives.front().indices.back() = 1000; // no such vertex
    EXPECT_FALSE(isConvexSurface(broken));
    // A sphere is convex, but finer than the test looks at.
    const GltfModel sphere = makeUvSphere(64, 32);
    size_t triangles = 0;
    for (const GltfPrimitive& primitive : sphere.primitives)
        triangles += primitive.indices.size() / 3;
    ASSERT_GT(triangles, kConvexSurfaceMaxTriangles);
    EXPECT_FALSE(isConvexSurface(sphere));
    EXPECT_TRUE(isConvexSurface(makeUvSphere(12, 8)));
}

} // namespace
} // namespace lumar
