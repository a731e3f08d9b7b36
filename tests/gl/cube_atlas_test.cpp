// shaders_es/cube_atlas.glsl, the cube lookup in a 2D atlas that mesh.frag, phantom.frag and
// the environment-map passes use, against the CPU cube lookup (cube_map.h's
// sampleCubeBilinear: GL's face selection, bilinear within the face, clamped at its edges),
// at directions on and near every face's edges and corners and at random ones, at level 0
// and at a mip level. Each face holds a constant of its own in red (10, 20, ... 60) and
// gradients in green and blue: a texel of a neighbouring cell blended in moves red by at
// least 10 times its weight; the texels of the cells that no face covers (cells are at least
// 64 px wide) hold 1000. cubeBankLevelUv (the same lookup split for sample loops) must find
// the same atlas coordinates.
#include <cmath>
#include <cstdio>
#include <optional>
#include <random>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "core/error.h"
#include "embedded_shaders.h"
#include "gl_readback.h"
#include "gles_renderer/gl/egl_context.h"
#include "gles_renderer/gl/gl_check.h"
#include "gles_renderer/ibl/cube_map.h"
#include "gles_renderer/ibl_gpu/ibl_maps.h"
#include "test_shader.h"

namespace lumar {
namespace {

constexpr int kFaceSize = 8; // level 0; level 1 has 4-px faces
constexpr int kColumns = 64;

const char* kMain = R"(
uniform sampler2D uDirections; // RGBA32F, xyz a direction
uniform sampler2D uAtlas;      // RGBA16F cube atlas, two levels
uniform vec2 uAtlasSize;
uniform float uLod;
out vec4 fragColor;
void main()
{
    vec3 d = texelFetch(uDirections, ivec2(gl_FragCoord.xy), 0).xyz;
    vec2 uv = cubeAtlasUv(d, uAtlasSize, uLod);
    // The split lookup of the sample loops must find the same place: otherwise the lookup
    // reads the right end of cell 2, past the face (1000).
    vec2 split = cubeBankLevelUv(d, cubeBankLevel(uAtlasSize, vec2(0.0, 1.0), uLod));
    fragColor = textureLod(uAtlas, distance(uv, split) < 1e-5 ? uv : vec2(0.999, 0.25), uLod);
}
)";

// Face f: red 10 (f + 1) (one more at level 1, so a lookup at the wrong level shows), green
// and blue gradients across s and t (steps that half floats hold exactly).
CubeMapF makeCube(int size, float levelOffset)
{
    CubeMapF cube;
    cube.size = size;
    for (int f = 0; f < 6; ++f) {
        ImageF& face = cube.faces[size_t(f)];
        face = ImageF(size, size, 3);
        for (int y = 0; y < size; ++y)
            for (int x = 0; x < size; ++x) {
                float* p = face.at(x, y);
                p[0] = 10.0f * float(f + 1) + levelOffset;
                p[1] = float(x) / float(size) + 0.25f * float(f % 2);
                p[2] = float(y * y) / float(size * size) + 0.125f * float(f / 2);
            }
    }
    return cube;
}

// The cube as level `level` of the atlas of kFaceSize-px faces (RGBA floats, row 0 at t = 0).
std::vector<float> atlasTexels(const CubeMapF& cube, int level)
{
    const glm::ivec2 extent = cubeAtlasSize(kFaceSize) >> level;
    const int width = extent.x;
    std::vector<float> texels(size_t(width) * size_t(extent.y) * 4, 1000.0f);
    for (int f = 0; f < 6; ++f) {
        const glm::ivec2 origin = cubeAtlasCellOrigin(f, kFaceSize) >> level;
        for (int y = 0; y < cube.size; ++y)
            for (int x = 0; x < cube.size; ++x) {
                float* t = &texels[(size_t(origin.y + y) * size_t(width) + size_t(origin.x + x)) * 4];
                const float* p = cube.faces[size_t(f)].at(x, y);
                t[0] = p[0];
                t[1] = p[1];
                t[2] = p[2];
                t[3] = 1.0f;
            }
    }
    return texels;
}

// On and near every face's edges and corners (and its centre), the cube's own corner and
// edge directions (ties between axes), and random ones.
std::vector<glm::vec3> makeDirections()
{
    std::vector<glm::vec3> directions;
    const float coordinates[] = {0.0f, 1e-4f,   0.01f, 0.03f, 0.0625f, 0.1f, 0.5f,
                                 0.9f, 0.9375f, 0.97f, 0.99f, 0.9999f, 1.0f};
    for (int f = 0; f < 6; ++f)
        for (const float s : coordinates)
            for (const float t : coordinates)
                directions.push_back(cubeTexelDirection(f, s, t));
    for (int x = -1; x <= 1; ++x)
        for (int y = -1; y <= 1; ++y)
            for (int z = -1; z <= 1; ++z)
                if (x != 0 || y != 0 || z != 0)
                    directions.emplace_back(float(x), float(y), float(z));
    std::mt19937 random(7);
    std::normal_distribution<float> normal;
    while (directions.size() % kColumns != 0 || directions.size() < 2048)
        directions.emplace_back(normal(random), normal(random), normal(random));
    return directions;
}

TEST(CubeAtlas, LookupMatchesTheCpuCubeLookupAndStaysInsideTheFace)
{
    LUMAR_CONTEXT_OR_SKIP(context);
    const CubeMapF level0 = makeCube(kFaceSize, 0.0f), level1 = makeCube(kFaceSize / 2, 1.0f);
    GlTexture atlas = GlTexture::create();
    glBindTexture(GL_TEXTURE_2D, atlas.name());
    const glm::ivec2 extent = cubeAtlasSize(kFaceSize);
    ASSERT_GT(extent.x, kAtlasColumns * kFaceSize) << "the cells are wider than the faces (a tile wide)";
    glTexStorage2D(GL_TEXTURE_2D, 2, GL_RGBA16F, extent.x, extent.y);
    for (int level = 0; level < 2; ++level) {
        const CubeMapF& cube = level == 0 ? level0 : level1;
        glTexSubImage2D(GL_TEXTURE_2D, level, 0, 0, extent.x >> level, extent.y >> level, GL_RGBA, GL_FLOAT,
                        atlasTexels(cube, level).data());
    }
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR_MIPMAP_LINEAR);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);

    const std::vector<glm::vec3> directions = makeDirections();
    const int rows = int(directions.size()) / kColumns;
    std::vector<float> input;
    for (const glm::vec3& d : directions)
        input.insert(input.end(), {d.x, d.y, d.z, 0.0f});
    GlTexture directionTexture = GlTexture::create();
    glBindTexture(GL_TEXTURE_2D, directionTexture.name());
    glTexStorage2D(GL_TEXTURE_2D, 1, GL_RGBA32F, kColumns, rows);
    glTexSubImage2D(GL_TEXTURE_2D, 0, 0, 0, kColumns, rows, GL_RGBA, GL_FLOAT, input.data());

    const std::string fragment = "#version 300 es\nprecision highp float;\nprecision highp sampler2D;\n" +
                                 std::string(shaders::source("cube_atlas.glsl")) + kMain;
    const GlProgram program = test::linkFullscreenTestProgram(fragment);

    GlTexture output = GlTexture::create();
    glBindTexture(GL_TEXTURE_2D, output.name());
    glTexStorage2D(GL_TEXTURE_2D, 1, GL_RGBA32F, kColumns, rows);
    GlFramebuffer framebuffer = GlFramebuffer::create();
    glBindFramebuffer(GL_FRAMEBUFFER, framebuffer.name());
    glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, output.name(), 0);
    checkFramebufferComplete("the cube-atlas probe target");
    glViewport(0, 0, kColumns, rows);
    glUseProgram(program.name());
    glActiveTexture(GL_TEXTURE0);
    glBindTexture(GL_TEXTURE_2D, directionTexture.name());
    glActiveTexture(GL_TEXTURE1);
    glBindTexture(GL_TEXTURE_2D, atlas.name());
    glUniform1i(glGetUniformLocation(program.name(), "uDirections"), 0);
    glUniform1i(glGetUniformLocation(program.name(), "uAtlas"), 1);
    glUniform2f(glGetUniformLocation(program.name(), "uAtlasSize"), float(extent.x), float(extent.y));
    GlVertexArray vertexArray = GlVertexArray::create();
    glBindVertexArray(vertexArray.name());

    for (int level = 0; level < 2; ++level) {
        const CubeMapF& cube = level == 0 ? level0 : level1;
        glUniform1f(glGetUniformLocation(program.name(), "uLod"), float(level));
        glDrawArrays(GL_TRIANGLES, 0, 3);
        checkGlError("drawing the cube-atlas probe");
        std::vector<float> read(size_t(kColumns) * size_t(rows) * 4);
        glReadPixels(0, 0, kColumns, rows, GL_RGBA, GL_FLOAT, read.data());

        // worstGradient: green and blue against the CPU lookup; worstFace: red against the
        // constant of the face the CPU selects (exact unless a neighbouring cell leaks in).
        float worstGradient = 0.0f, worstFace = 0.0f;
        for (size_t i = 0; i < directions.size(); ++i) {
            const glm::vec3 expected = sampleCubeBilinear(cube, directions[i]);
            const float* gpu = &read[i * 4];
            worstFace = std::max(worstFace, std::abs(gpu[0] - expected.r));
            worstGradient = std::max({worstGradient, std::abs(gpu[1] - expected.g), std::abs(gpu[2] - expected.b)});
        }
        std::printf("level %d (%d-px faces), %zu directions: worst |gpu - cpu| %.2e (gradients), %.2e (face "
                    "constant)\n",
                    level, cube.size, directions.size(), double(worstGradient), double(worstFace));
        // Bilinear weights in float on both sides: what remains is rounding of the
        // coordinates (texel steps of the gradients are 1/8 to 1/4; a neighbour's red
        // differs by >= 10).
        EXPECT_LT(worstGradient, 2e-3f) << "level " << level;
        EXPECT_LT(worstFace, 2e-3f) << "level " << level << ": a neighbouring cell leaks into the lookup";
    }
}

} // namespace
} // namespace lumar
