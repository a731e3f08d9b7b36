// The fake camera's surroundings: the configured equirectangular .hdr at infinity, turned into
// the world frame as the renderer turns it (core/environment_frame.h) and resampled into a
// cube map of packed code values, so a ray that misses the table costs one branch-free index
// computation (the ray loops vectorize it) and one load.
//
// The cube is the world's own: face 2a + s looks along world axis a (x, y, z), s = 0 for the
// positive and 1 for the negative direction; within a face, column i and row j cover the
// other two coordinates (in x, y, z order) divided by the major one, over [-1, 1].
//
// Texels are stored in square tiles of 32² (4 KiB, one page each), so that the texels a camera
// never looks at need not be baked nor held (LazyTexels): the fake camera's orbit sees 7 % of
// its 1024² cube over a whole period (2 % in the bench's first 45 frames), so baking it all
// held 24 MiB where 1.6 MiB are read (issue 18: memory).
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

#include "capture/fake_scene_shading.h"
#include "capture/packed_buffer.h"
#include "capture/shared_exponent_image.h"
#include "capture/srgb_encoding.h"
#include "capture/view_cone.h"
#include "core/image.h"

namespace lumar {

class EnvironmentCube {
public:
    static constexpr int kMinLog2Size = 6;
    static constexpr int kMaxLog2Size = 10;
    static constexpr int kLog2Tile = 5; // tiles of 32² texels, 4 KiB
    static constexpr int kTileTexels = 1 << (2 * kLog2Tile);

    // The face size for a camera of focal length `fx` pixels: the power of two at or above fx,
    // so a texel at a face's centre (2/size rad) spans at most about two pixels (2/fx rad);
    // 1024 for 1280x720 (0.11° texels, a third of the 1k map's 0.35°). Log2, in
    // [kMinLog2Size, kMaxLog2Size].
    static int log2SizeFor(double fx);

    // `equirect`: linear radiance, 3 channels (environment_map.h's layout), as loaded: the cube
    // holds max(radiance, 0) · intensity; faces of 2^log2Size texels a side.
    EnvironmentCube(const ImageF& equirect, float intensity, int log2Size);

    [[nodiscard]] int log2Size() const { return log2Size_; }
    // Texels in the whole cube, and tiles (texel index / kTileTexels).
    [[nodiscard]] size_t texelCount() const { return 6 * size_t(size_) * size_t(size_); }
    [[nodiscard]] int tileCount() const { return int(tileCones_.size()); }

    // The cube's texels as code values at `exposure` (linear radiance × exposure, encoded),
    // every tile of them.
    [[nodiscard]] PackedBuffer bake(float exposure, const SrgbEncoder& encoder) const;
    // Tile `tile`'s texels into `texels` (the whole cube's, index()'s layout); the same values
    // bake() gives them.
    void bakeTile(int tile, float exposure, const SrgbEncoder& encoder, fake_scene::PackedRgb* texels) const;
    // False only if no direction inside `view` has index() in tile `tile` (a conservative test:
    // a few tiles just outside the view may pass it).
    [[nodiscard]] bool tileMayBeSeen(int tile, const ViewCone& view) const;
    // True only if every direction index() may store in tile `tile` lies inside `cone`
    // (conservative too: a tile just inside may fail it).
    [[nodiscard]] bool tileWithin(int tile, const ViewCone& cone) const;

    // The linear radiance the cube stores towards world direction `d` (any length): the map
    // sampled bilinearly there.
    [[nodiscard]] glm::vec3 radiance(const glm::vec3& d) const;

    // The texel towards world direction (dx, dy, dz), not all zero, in a cube of faces
    // 2^log2Size a side. Branch-free, so the ray loops vectorize it.
    [[gnu::always_inline]] static inline int32_t index(float dx, float dy, float dz, int log2Size)
    {
        const float ax = std::abs(dx);
        const float ay = std::abs(dy);
        const float az = std::abs(dz);
        const bool xMajor = (ax >= ay) & (ax >= az);
        const bool yMajor = !xMajor & (ay >= az);
        const bool zMajor = !xMajor & !yMajor;
        const float major = xMajor ? dx : (yMajor ? dy : dz);
        const float first = xMajor ? dy : dx;
        const float second = zMajor ? dy : dz;
        // |first|, |second| <= |major|, so both coordinates land in [0, kSize]; the top edge
        // belongs to the last texel.
        const float size = float(1 << log2Size);
        const float half = 0.5f * size;
        const float last = size - 0.5f;
        const float scale = half / std::abs(major);
        const int32_t i = int32_t(std::min(first * scale + half, last));
        const int32_t j = int32_t(std::min(second * scale + half, last));
        const int32_t face = (xMajor ? 0 : (yMajor ? 2 : 4)) + (major < 0.0f ? 1 : 0);
        // Face, tile row, tile column, row and column within the tile.
        constexpr int32_t mask = (1 << kLog2Tile) - 1;
        return (face << (2 * log2Size)) | ((j >> kLog2Tile) << (log2Size + kLog2Tile)) |
               ((i >> kLog2Tile) << (2 * kLog2Tile)) | ((j & mask) << kLog2Tile) | (i & mask);
    }

private:
    // A tile's directions: the unit direction through its centre and the sine of the largest
    // angle from it to a direction index() may store in the tile.
    struct TileCone {
        glm::vec3 centre{0.0f};
        float sinRadius = 0.0f;
    };
    // Face f's directions m · (major + a · first + b · second) in the map's frame, for (a, b) in
    // [-1, 1]² (m: environmentFromWorld_), and the same axes in the world frame.
    struct FaceAxes {
        glm::vec3 major{0.0f}, first{0.0f}, second{0.0f};
    };
    static FaceAxes worldAxes(int face);
    [[nodiscard]] std::vector<TileCone> makeTileCones() const;

    SharedExponentImage equirect_;
    int log2Size_;
    int size_;
    glm::mat3 environmentFromWorld_;
    std::vector<TileCone> tileCones_;
};

} // namespace lumar
