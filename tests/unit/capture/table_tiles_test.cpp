// The fake camera's lit table in tiles (TableTexture::tiledIndex), lit as frames first see
// them: the layout gives every texel its own index, tile by tile, and the tiles a view may
// see (TableTexture::tileMayBeSeen) include every tile its rays meet and leave out most others.
#include <array>
#include <cmath>
#include <set>
#include <vector>

#include <gtest/gtest.h>

#include "capture/table_texture.h"

namespace lumar {
namespace {

TEST(TableTiles, EveryTexelHasItsOwnIndexWithinItsTile)
{
    constexpr int n = TableTexture::kResolution;
    std::vector<uint8_t> hits(size_t(n) * n, 0);
    for (int ty = 0; ty < n; ++ty) {
        for (int tx = 0; tx < n; ++tx) {
            const int32_t index = TableTexture::tiledIndex(tx, ty);
            ASSERT_GE(index, 0);
            ASSERT_LT(index, n * n);
            ++hits[size_t(index)];
            ASSERT_EQ(index / TableTexture::kTileTexels,
                      ty / TableTexture::kTileSide * TableTexture::kTilesPerSide + tx / TableTexture::kTileSide);
        }
    }
    for (const uint8_t h : hits) {
        ASSERT_EQ(h, 1);
    }
}

// A 1280x720 camera (fx = fy = 914 px, the fake camera's) at `eye` looking at `target`: the
// direction through pixel (u, v), pixel centres at integers.
struct Camera {
    glm::vec3 eye, right, down, forward;
    [[nodiscard]] glm::vec3 ray(float u, float v) const
    {
        return forward + (u - 639.5f) / 914.0f * right + (v - 359.5f) / 914.0f * down;
    }
};

Camera lookAt(glm::vec3 eye, glm::vec3 target)
{
    Camera c;
    c.eye = eye;
    c.forward = glm::normalize(target - eye);
    c.right = glm::normalize(glm::cross(c.forward, glm::vec3(0.0f, 0.0f, 1.0f)));
    c.down = glm::cross(c.forward, c.right);
    return c;
}

TEST(TableTiles, AViewSeesEveryTileItsRaysMeetAndFewOthers)
{
    // The orbit's extremes: low and far, high and near, off to a side (fake_trajectory.cpp).
    const std::vector<Camera> cameras = {
        lookAt({0.0f, -0.61f, 0.51f}, {0.02f, 0.01f, 0.0f}),
        lookAt({0.0f, -0.21f, 0.45f}, {-0.03f, 0.0f, 0.0f}),
        lookAt({-0.45f, -0.4f, 0.55f}, {0.0f, 0.02f, 0.0f}),
    };
    for (const Camera& camera : cameras) {
        const ViewCone view = ViewCone::spannedBy({camera.ray(-0.5f, -0.5f), camera.ray(1279.5f, -0.5f),
                                                   camera.ray(1279.5f, 719.5f), camera.ray(-0.5f, 719.5f)});
        std::set<int> met;
        // Rays as the fake camera casts them (2 × 2 per pixel, a quarter pixel from the
        // centre), on every row and column near the image's edges and every 4th inside.
        for (float v = -0.25f; v <= 719.75f; v += (v < 8.0f || v > 711.0f) ? 0.5f : 2.0f) {
            for (float u = -0.25f; u <= 1279.75f; u += (u < 8.0f || u > 1271.0f) ? 0.5f : 2.0f) {
                const glm::vec3 d = camera.ray(u, v);
                if (d.z >= -1e-3f) {
                    continue;
                }
                const float t = -camera.eye.z / d.z;
                const float fx = (camera.eye.x + t * d.x + fake_scene::kTableHalfSize) * TableTexture::kTexelsPerMetre;
                const float fy = (camera.eye.y + t * d.y + fake_scene::kTableHalfSize) * TableTexture::kTexelsPerMetre;
                if (fx < 0.0f || fy < 0.0f || fx >= float(TableTexture::kResolution) ||
                    fy >= float(TableTexture::kResolution)) {
                    continue;
                }
                met.insert(TableTexture::tiledIndex(int(fx), int(fy)) / TableTexture::kTileTexels);
            }
        }
        int seen = 0;
        for (int tile = 0; tile < TableTexture::kTileCount; ++tile) {
            seen += TableTexture::tileMayBeSeen(tile, camera.eye, view) ? 1 : 0;
        }
        for (const int tile : met) {
            ASSERT_TRUE(TableTexture::tileMayBeSeen(tile, camera.eye, view)) << "tile " << tile;
        }
        // Beyond the tiles the rays meet: the tiles its edges cross, partly seen.
        std::printf("tiles met %zu, may be seen %d of %d\n", met.size(), seen, TableTexture::kTileCount);
        EXPECT_LT(seen, int(met.size()) + 100);
        EXPECT_LT(seen, TableTexture::kTileCount);
    }
}

} // namespace
} // namespace lumar
