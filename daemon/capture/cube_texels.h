// The environment cube's code values at one exposure, baked a tile at a time when a frame
// first looks that way: the fake camera's orbit reads a few percent of its cube, and the
// tiles it never looks at stay unbaked and cost no memory (issue 18: the 1024² cube held
// 24 MiB baked whole; car.toml's camera reads 1.6 MiB of it over a whole period).
#pragma once

#include <mutex>
#include <vector>

#include "capture/environment_cube.h"
#include "capture/packed_buffer.h"
#include "capture/srgb_encoding.h"

namespace lumar {

class CubeTexels {
public:
    // Nothing baked yet. `cube` and `encoder` must outlive this.
    CubeTexels(const EnvironmentCube& cube, float exposure, const SrgbEncoder& encoder);

    // Bakes the tiles not yet baked that a direction inside `view` may read (conservatively:
    // EnvironmentCube::tileMayBeSeen). Safe to call from several threads: each returns once
    // every tile its view needs is baked. A frame reads only texels of its own view.
    void prepare(const ViewCone& view) const;
    // Bakes every tile not yet baked.
    void prepareAll() const;

    // The texels, in EnvironmentCube::index()'s layout; a tile not yet prepared reads as zero.
    [[nodiscard]] const fake_scene::PackedRgb* texels() const { return texels_.get(); }
    [[nodiscard]] int tilesBaked() const;

private:
    template <typename Needed> void bakeWhere(Needed needed) const;

    const EnvironmentCube& cube_;
    float exposure_;
    const SrgbEncoder& encoder_;
    SparsePackedBuffer texels_;
    mutable std::mutex mutex_;
    mutable std::vector<bool> baked_; // per tile, under mutex_
    mutable int tilesBaked_ = 0;      // under mutex_
};

} // namespace lumar
