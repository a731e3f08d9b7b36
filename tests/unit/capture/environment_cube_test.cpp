// The fake camera's environment cube: its tiled layout gives every texel its own index, and
// a cube baked tile by tile as views need it (LazyTexels with tileMayBeSeen) reads, inside
// each view, exactly what the cube baked whole holds, while baking a small part of it.
#include <array>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <vector>

#include <gtest/gtest.h>

#include "capture/environment_cube.h"
#include "capture/lazy_texels.h"
#include "gles_renderer/assets/environment_map.h"

namespace lumar {
namespace {

const ImageF& sunset()
{
    static const ImageF map =
        loadHdrImage(std::filesystem::path(LUMAR_SOURCE_DIR) / "daemon/assets/env/venice_sunset_1k.hdr");
    return map;
}

// The direction through the centre of texel (i, j) of face `face` (the layout's definition).
glm::vec3 texelDirection(int face, int i, int j, int size)
{
    const int axis = face / 2;
    glm::vec3 d(0.0f);
    d[axis] = face % 2 == 0 ? 1.0f : -1.0f;
    d[axis == 0 ? 1 : 0] = -1.0f + (float(i) + 0.5f) * 2.0f / float(size);
    d[axis == 2 ? 1 : 2] = -1.0f + (float(j) + 0.5f) * 2.0f / float(size);
    return d;
}

TEST(EnvironmentCube, EveryTexelHasItsOwnIndexAndTilesArePages)
{
    constexpr int kLog2 = 7;
    constexpr int kSize = 1 << kLog2;
    std::vector<int> hits(6 * kSize * kSize, 0);
    for (int face = 0; face < 6; ++face) {
        for (int j = 0; j < kSize; ++j) {
            for (int i = 0; i < kSize; ++i) {
                const glm::vec3 d = texelDirection(face, i, j, kSize);
                const int32_t index = EnvironmentCube::index(d.x, d.y, d.z, kLog2);
                ASSERT_GE(index, 0);
                ASSERT_LT(index, int32_t(hits.size()));
                ++hits[size_t(index)];
                // A tile is kTileTexels consecutive texels: 32 × 32 neighbours on one face.
                const int tilesPerSide = kSize >> EnvironmentCube::kLog2Tile;
                const int tile = index / EnvironmentCube::kTileTexels;
                EXPECT_EQ(tile, (face * tilesPerSide + (j >> EnvironmentCube::kLog2Tile)) * tilesPerSide +
                                    (i >> EnvironmentCube::kLog2Tile));
            }
        }
    }
    for (const int h : hits) {
        ASSERT_EQ(h, 1);
    }
}

// The four corner directions of a 1280x720 camera (fx = fy = 914 px, the fake camera's)
// looking along `forward` with `up` roughly up.
std::array<glm::vec3, 4> cameraCorners(glm::vec3 forward, glm::vec3 up)
{
    forward = glm::normalize(forward);
    const glm::vec3 right = glm::normalize(glm::cross(forward, up));
    const glm::vec3 down = glm::cross(forward, right);
    const float x = 640.0f / 914.0f;
    const float y = 360.0f / 914.0f;
    return {forward - x * right - y * down, forward + x * right - y * down, forward + x * right + y * down,
            forward - x * right + y * down};
}

TEST(EnvironmentCube, AViewReadsWhatTheWholeCubeHoldsFromFewTiles)
{
    const EnvironmentCube cube(sunset(), 1.0f, 10);
    const SrgbEncoder encoder;
    const PackedBuffer whole = cube.bake(2.0f, encoder);
    const std::vector<std::array<glm::vec3, 2>> views = {
        {glm::vec3(0.0f, 1.0f, -0.9f), glm::vec3(0.0f, 0.0f, 1.0f)},   // down at the table, as the orbit looks
        {glm::vec3(1.0f, 1.0f, 1.0f), glm::vec3(0.0f, 0.0f, 1.0f)},    // into a corner of three faces
        {glm::vec3(-0.2f, 0.1f, -1.0f), glm::vec3(0.0f, 1.0f, 0.0f)},  // straight down
        {glm::vec3(1.0f, -0.05f, 0.02f), glm::vec3(0.3f, 0.0f, 1.0f)}, // along a face's centre, rolled
    };
    for (const auto& [forward, up] : views) {
        const LazyTexels lazy(cube.texelCount(), cube.tileCount(), [&](int tile, fake_scene::PackedRgb* texels) {
            cube.bakeTile(tile, 2.0f, encoder, texels);
        });
        const std::array<glm::vec3, 4> corners = cameraCorners(forward, up);
        const ViewCone view = ViewCone::spannedBy(corners);
        lazy.prepare([&](int tile) { return cube.tileMayBeSeen(tile, view); });
        // The view covers ~0.8 sr of the sphere's 12.6: a few percent of the tiles, with the
        // tiles its edges cross.
        EXPECT_LT(lazy.tilesBaked(), cube.tileCount() / 8);
        EXPECT_GT(lazy.tilesBaked(), cube.tileCount() / 50);
        // Directions over the whole view, its edges and corners included.
        constexpr int kSteps = 400;
        size_t lit = 0;
        for (int v = 0; v <= kSteps; ++v) {
            const float t = float(v) / kSteps;
            const glm::vec3 left = corners[0] + t * (corners[3] - corners[0]);
            const glm::vec3 right = corners[1] + t * (corners[2] - corners[1]);
            for (int u = 0; u <= kSteps; ++u) {
                const glm::vec3 d = left + (float(u) / kSteps) * (right - left);
                const size_t index = size_t(EnvironmentCube::index(d.x, d.y, d.z, cube.log2Size()));
                ASSERT_EQ(lazy.texels()[index], whole[index])
                    << "view " << forward.x << "," << forward.y << "," << forward.z << " at u " << u << " v " << v;
                lit += whole[index] != 0 ? 1 : 0;
            }
        }
        // Unbaked tiles read as zero: the comparison means something only where the map is lit.
        EXPECT_GT(lit, size_t(kSteps * kSteps) * 9 / 10);
    }
}

TEST(EnvironmentCube, ATileWithinAConeHasEveryTexelInsideIt)
{
    // The cone a 1.2 m table subtends from a camera above it (the tiles the table hides).
    const EnvironmentCube cube(sunset(), 1.0f, 8);
    const int size = 1 << cube.log2Size();
    const int tilesPerSide = size >> EnvironmentCube::kLog2Tile;
    for (const glm::vec3 eye : {glm::vec3(0.0f, -0.4f, 0.5f), glm::vec3(0.3f, -0.5f, 0.3f)}) {
        const float h = 0.6f;
        const ViewCone table = ViewCone::spannedBy({glm::vec3(-h, -h, 0.0f) - eye, glm::vec3(h, -h, 0.0f) - eye,
                                                    glm::vec3(h, h, 0.0f) - eye, glm::vec3(-h, h, 0.0f) - eye});
        int within = 0;
        int touched = 0; // tiles with a texel inside the cone
        for (int tile = 0; tile < cube.tileCount(); ++tile) {
            const int face = tile / (tilesPerSide * tilesPerSide);
            const int j0 = (tile / tilesPerSide % tilesPerSide) << EnvironmentCube::kLog2Tile;
            const int i0 = (tile % tilesPerSide) << EnvironmentCube::kLog2Tile;
            bool allInside = true;
            bool anyInside = false;
            // Its texels' centres, and a texel further all round (where index() may round to).
            for (int j = j0 - 1; j <= j0 + 32; ++j) {
                for (int i = i0 - 1; i <= i0 + 32; ++i) {
                    const glm::vec3 d = texelDirection(face, i, j, size);
                    bool inside = true;
                    for (const glm::vec3& n : table.inward) {
                        inside = inside && glm::dot(n, d) >= 0.0f;
                    }
                    allInside = allInside && inside;
                    anyInside = anyInside || inside;
                }
            }
            if (cube.tileWithin(tile, table)) {
                ++within;
                EXPECT_TRUE(allInside) << "tile " << tile;
            }
            touched += anyInside ? 1 : 0;
        }
        // Most tiles the table covers are found within it: a tile's circle is a little larger.
        EXPECT_GT(within, touched / 2);
    }
}

TEST(EnvironmentCube, TilesBakedOneByOneAreTheCubeBakedWhole)
{
    const EnvironmentCube cube(sunset(), 1.0f, 8);
    const SrgbEncoder encoder;
    const PackedBuffer whole = cube.bake(0.7f, encoder);
    const LazyTexels lazy(cube.texelCount(), cube.tileCount(),
                          [&](int tile, fake_scene::PackedRgb* texels) { cube.bakeTile(tile, 0.7f, encoder, texels); });
    lazy.prepareAll();
    EXPECT_EQ(lazy.tilesBaked(), cube.tileCount());
    EXPECT_EQ(std::memcmp(lazy.texels(), whole.get(), cube.texelCount() * sizeof(fake_scene::PackedRgb)), 0);
}

} // namespace
} // namespace lumar
