// Map banks (gles_renderer/ibl_gpu/ibl_maps.h): the maps of several sets drawn side by side
// in one pass per kind must equal each set's maps built alone, slot for slot: a wrong slot
// offset in any pass (mirror faces, SH sums, diffuse, either glossy prefilter) reads or
// writes another slot's texels.
#include <algorithm>
#include <cmath>
#include <vector>

#include <gtest/gtest.h>

#include "gl_readback.h"
#include "gles_renderer/ibl/cube_face_camera.h"
#include "gles_renderer/ibl_gpu/ibl_pipeline.h"
#include "test_shader.h"

namespace lumar {
namespace {

// Face `face` of set `set`: a colour that differs from face to face and from set to set,
// and a bright square off the face's centre (detail for the glossy lobes to blur).
void drawTestFace(int set, int face, int size)
{
    GLint box[4] = {};
    glGetIntegerv(GL_SCISSOR_BOX, box);
    const float s = float(set), f = float(face);
    glClearColor(0.1f + 0.2f * std::fmod(f + s, 3.0f), 0.15f + 0.1f * std::fmod(2.0f * f + s, 5.0f),
                 0.2f + 0.3f * s + 0.05f * f, 1.0f);
    glClear(GL_COLOR_BUFFER_BIT);
    const int side = size / 4;
    glScissor(box[0] + (set + face) % 3 * side, box[1] + side, side, side);
    glClearColor(4.0f + s, 2.0f, 1.0f + f, 1.0f);
    glClear(GL_COLOR_BUFFER_BIT);
    glScissor(box[0], box[1], box[2], box[3]);
}

// The largest difference of b from a, relative to a's largest value.
double relativeError(const CubeMapF& a, const CubeMapF& b)
{
    double worst = 0.0, peak = 0.0;
    for (size_t f = 0; f < size_t(kCubeFaces); ++f)
        for (size_t i = 0; i < a.faces[f].data.size(); ++i) {
            peak = std::max(peak, double(std::abs(a.faces[f].data[i])));
            worst = std::max(worst, double(std::abs(a.faces[f].data[i] - b.faces[f].data[i])));
        }
    return worst / std::max(peak, 1e-9);
}

// Float maps, or RGBA8 RGBM ones (whose SH sums run on the CPU, slot by slot).
class IblBank : public ::testing::TestWithParam<bool> {};

TEST_P(IblBank, EachSlotEqualsTheSameMapsBuiltAlone)
{
    LUMAR_CONTEXT_OR_SKIP(context);
    IblSettings settings;
    settings.forceRgbm = GetParam();
    IblPipeline pipeline(settings);
    const bool rgbm = pipeline.rgbm();
    const auto read = [&](GLuint texture, int size, int slot, int slots) {
        return rgbm ? test::readCubeAtlasRgbm(texture, size, 0, slot, slots)
                    : test::readCubeAtlas(texture, size, 0, slot, slots);
    };
    constexpr int kSlots = 3;
    ASSERT_GE(pipeline.maxBankSlots(kSlots), kSlots);
    IblMaps bank = pipeline.createMaps(kSlots);
    // Slots 0 and 2 drawn, slot 1 cleared and out of the derived passes: each slot's passes
    // must keep to it whatever its place.
    std::vector<IblPipeline::MirrorSlot> slots{{1, 0, false, {}}}; // cleared to black alone
    for (const int set : {0, 2})
        slots.push_back({set, 0, false, [&, set](int face) { drawTestFace(set, face, settings.mirrorSize); }});
    pipeline.renderMirrorSlots(bank, slots);
    const std::vector<int> drawn{0, 2};
    pipeline.projectSHSlots(bank, drawn);
    pipeline.prefilterSlots(bank, drawn);

    for (const int set : drawn) {
        IblMaps alone = pipeline.createMaps();
        pipeline.renderMirror(alone, nullptr, [&](int face) { drawTestFace(set, face, settings.mirrorSize); });
        pipeline.updateDerivedMaps(alone);
        const auto compare = [&](GLuint bankTexture, GLuint aloneTexture, int size, const char* what) {
            const CubeMapF expected = read(aloneTexture, size, 0, 1);
            const CubeMapF got = read(bankTexture, size, set, kSlots);
            EXPECT_LT(relativeError(expected, got), 1e-3) << what << " of slot " << set;
        };
        compare(bank.mirror.name(), alone.mirror.name(), settings.mirrorSize, "mirror");
        compare(bank.diffuse.name(), alone.diffuse.name(), settings.diffuseSize, "diffuse");
        compare(bank.glossy1.name(), alone.glossy1.name(), settings.glossy1Size, "glossy-1");
        compare(bank.glossy2.name(), alone.glossy2.name(), settings.glossy2Size, "glossy-2");
        const ImageF expected = test::readTexture2D(alone.coefficients.name(), 1, 9);
        const ImageF got = test::readTexture2D(bank.coefficients.name(), kSlots, 9);
        for (int j = 0; j < 9; ++j)
            for (int c = 0; c < 3; ++c)
                EXPECT_NEAR(got.at(set, j)[c], expected.at(0, j)[c], 1e-3 * std::abs(expected.at(0, 0)[c]))
                    << "SH coefficient " << j << " of slot " << set;
    }
    // The undrawn slot stayed black: nothing of its neighbours' faces spilled into it.
    const CubeMapF idle = read(bank.mirror.name(), settings.mirrorSize, 1, kSlots);
    for (const ImageF& face : idle.faces)
        EXPECT_EQ(*std::max_element(face.data.begin(), face.data.end()), 0.0f);
}

INSTANTIATE_TEST_SUITE_P(Formats, IblBank, ::testing::Values(false, true),
                         [](const ::testing::TestParamInfo<bool>& format) { return format.param ? "Rgbm" : "Float"; });

} // namespace
} // namespace lumar
