// The tangent-rotation map's wrap (the paper's figure 1 swirl): the map holds an angle / pi, so
// a texel just below 1 turns the tangent as one just above 0 does. Filtered across that wrap
// (bilinear, or mipmap averages) the angle passes through 1/2, a 90 degree turn, and an
// anisotropic highlight showed a line along it; the renderer samples the map nearest without
// mipmaps (gpu_model.cpp), and this test holds it to that.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>

#include <glm/gtc/matrix_transform.hpp>
#include <gtest/gtest.h>

#include "gl_test_support.h"
#include "gles_renderer/assets/lafortune_material.h"

namespace lumar {
namespace {

constexpr int kWidth = 160, kHeight = 120;
constexpr double kFocal = 800.0, kCx = 79.5, kCy = 59.5;

// The brushed_metal preset (C = -1, -0.8, 1, n = 200: no diffuse, a highlight that dies when
// the view leans along the bitangent) with a rotation map of 8 x 2 texels: the left four
// columns 254/255 (a turn of 179.3 degrees), the right four 1/255 (0.7 degrees), so the
// tangent is within 0.7 degrees of the uv's u axis everywhere and the angle wraps between
// columns 3 and 4 (u = 1/2).
GltfModel wrappingSwirlQuad()
{
    GltfMaterial material;
    material.hasLafortune = true;
    material.lafortune = *materialPreset("brushed_metal");
    material.lafortune.tangentRotation = 1.0f; // angle / pi = the texel
    material.tangentRotationTexture = 0;
    // u along the model's x, v along its y, facing -z (cameraFacingRectangle).
    GltfModel model = test::cameraFacingRectangle(-0.3f, -0.2f, 0.3f, 0.2f, material);
    GltfTexture rotation;
    rotation.image = Image8(8, 2, 4);
    for (int y = 0; y < 2; ++y)
        for (int x = 0; x < 8; ++x) {
            uint8_t* texel = rotation.image.at(x, y);
            texel[0] = texel[1] = texel[2] = x < 4 ? 254 : 1;
            texel[3] = 255;
        }
    rotation.srgb = false;
    model.textures.push_back(rotation);
    // What a glTF asking for filtering would get: the renderer overrides it for this map.
    GltfSampler linear;
    linear.minFilter = 9987; // GL_LINEAR_MIPMAP_LINEAR
    linear.magFilter = 9729; // GL_LINEAR
    model.textureSamplers.push_back(linear);
    return model;
}

// The quad 4 m ahead, turned 45 degrees about the camera's y axis: the view leans along the
// tangent (u), where the lobe (C_x = -1) keeps its full magnitude; turned 90 degrees the view
// leans along the bitangent (C_y = -0.8) and the highlight falls to |C v|^200 ~ 1e-9. The
// wrap line (model x = 0) is image column kCx. The long focal length keeps the views along
// the wrap line nearly parallel: one leaning off the middle row along the bitangent makes the
// texels' own step across the wrap (1.4 degrees) show, steeply at n = 200.
TEST(TangentRotation, TheHighlightStaysContinuousAcrossTheAnglesWrap)
{
    LUMAR_RENDERER_OR_SKIP(renderer, kWidth, kHeight);
    renderer.setEnvironment(test::uniformEnvironment(1.0f), 1.0f);
    const ModelId quad = renderer.addModel(wrappingSwirlQuad());
    const glm::dmat4 cameraFromModel =
        test::translation(0.0, 0.0, 4.0) * glm::rotate(glm::dmat4(1.0), glm::radians(45.0), glm::dvec3(0.0, 1.0, 0.0));
    const DrawItem items[] = {{quad, cameraFromModel, -1}};
    renderer.render(test::solidImage(kWidth, kHeight, 0, 0, 0),
                    test::makeIntrinsics(kWidth, kHeight, kFocal, kFocal, kCx, kCy), items);
    Image8 out;
    renderer.readback(out);

    // Along the rows through the middle of the quad (it spans rows ~20-100), each pixel within
    // kBand columns of the wrap against its neighbour on the left: the highlight's gradient
    // along a row is under 1 code value a pixel, and the texels' own step moves it by at most
    // 3 (nearest, as the renderer samples the map); filtered bilinearly, the angle would
    // sweep through 90 degrees over the texel (~10 columns) between the two columns' centres
    // and the highlight fall from ~200 to black and back (a step of 118 between neighbours).
    constexpr int kBand = 12;
    constexpr int kMaxStep = 8; // code values between neighbouring pixels
    const int wrap = int(std::lround(kCx));
    int worst = 0, worstX = 0, worstY = 0;
    double highlight = 0.0;
    int rows = 0;
    for (int y = 40; y <= 80; ++y) {
        highlight += 0.5 * (out.at(wrap - 2 * kBand, y)[1] + out.at(wrap + 2 * kBand, y)[1]);
        ++rows;
        for (int x = wrap - kBand; x <= wrap + kBand; ++x) {
            const int step = std::abs(out.at(x, y)[1] - out.at(x - 1, y)[1]);
            if (step > worst) {
                worst = step;
                worstX = x;
                worstY = y;
            }
        }
    }
    highlight /= rows;
    std::printf(
        "highlight beside the wrap %.1f; largest step between neighbours within %d columns of it %d (at %d,%d)\n",
        highlight, kBand, worst, worstX, worstY);
    // The test means something only where the highlight is bright beside the wrap.
    ASSERT_GT(highlight, 120.0);
    EXPECT_LE(worst, kMaxStep) << "a line along the rotation map's wrap at " << worstX << "," << worstY;
}

} // namespace
} // namespace lumar
