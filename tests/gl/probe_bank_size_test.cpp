// EnvironmentProbes keeps the objects' maps in banks of up to kBankSlots sets (ibl_maps.h).
// A bank is sized to the objects that need maps: a scene of two objects allocates two sets,
// not four (each 64 px set is ~0.4 MB of textures).
#include <gtest/gtest.h>

#include "gl_test_support.h"
#include "gles_renderer/assets/builtin_shapes.h"
#include "gles_renderer/scene/environment_probes.h"

namespace lumar {
namespace {

constexpr int kWidth = 64, kHeight = 48;

TEST(ProbeBanks, ABankHoldsAsManySetsAsThereAreObjects)
{
    LUMAR_RENDERER_OR_SKIP(renderer, kWidth, kHeight);
    static_assert(EnvironmentProbes::kBankSlots > 2);
    renderer.setEnvironment(test::uniformEnvironment(0.2f), 1.0f);
    const ModelId sphere = renderer.addModel(makeUvSphere(16, 8));
    const ModelId cube = renderer.addModel(makeCube());
    const glm::dmat4 small(glm::dmat3(0.05));
    std::vector<DrawItem> items = {{sphere, test::translation(-0.06, 0.0, 0.5) * small, 0},
                                   {cube, test::translation(0.06, 0.0, 0.5) * small, 1}};
    const CameraIntrinsics intrinsics = test::makeIntrinsics(kWidth, kHeight, 80, 80, 31.5, 23.5);
    renderer.render(test::solidImage(kWidth, kHeight, 0, 0, 0), intrinsics, items);
    for (int object = 0; object < 2; ++object) {
        const IblMaps* maps = renderer.objectMaps(object);
        ASSERT_NE(maps, nullptr);
        EXPECT_EQ(maps->textures().slots, 2) << "object " << object;
    }
    // A third object later gets a bank of its own and its maps.
    const ModelId third = renderer.addModel(makeCube());
    items.push_back({third, test::translation(0.0, 0.06, 0.5) * small, 2});
    renderer.render(test::solidImage(kWidth, kHeight, 0, 0, 0), intrinsics, items);
    ASSERT_NE(renderer.objectMaps(2), nullptr);
    EXPECT_EQ(renderer.objectMaps(2)->textures().slots, 1);
    EXPECT_EQ(renderer.objectMaps(0)->textures().slots, 2);
}

} // namespace
} // namespace lumar
