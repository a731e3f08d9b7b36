// Code values baked a tile at a time when a frame first needs them (the fake camera's
// environment cube): its orbit reads a few percent of its 1024² cube, and the tiles no frame
// reads stay unbaked and cost no memory (issue 18: the cube held 24 MiB baked whole, of which
// car.toml's camera reads 1.6 MiB over a whole period).
#pragma once

#include <functional>
#include <mutex>
#include <vector>

#include "capture/packed_buffer.h"

namespace lumar {

class LazyTexels {
public:
    // bakeTile(tile, texels) writes tile `tile`'s texels into `texels` (the whole buffer);
    // tiles are the buffer's runs of texelCount / tileCount texels, a whole number of pages.
    using BakeTile = std::function<void(int tile, fake_scene::PackedRgb* texels)>;
    LazyTexels(size_t texelCount, int tileCount, BakeTile bakeTile);

    // Bakes the tiles not yet baked for which needed(tile) holds. Safe to call from several
    // threads: each returns once every tile it needs is baked.
    template <typename Needed> void prepare(Needed needed) const
    {
        // Baking under the lock: a frame's new tiles take a few ms at most, and a second
        // thread needing the same tiles has to wait for them anyway.
        const std::lock_guard lock(mutex_);
        for (int tile = 0; tile < int(baked_.size()); ++tile) {
            if (!baked_[size_t(tile)] && needed(tile)) {
                bakeTile_(tile, texels_.get());
                baked_[size_t(tile)] = true;
                ++tilesBaked_;
            }
        }
    }
    void prepareAll() const
    {
        prepare([](int) { return true; });
    }

    // The texels; a tile not yet prepared reads as zero.
    [[nodiscard]] const fake_scene::PackedRgb* texels() const { return texels_.get(); }
    [[nodiscard]] int tilesBaked() const;

private:
    BakeTile bakeTile_;
    SparsePackedBuffer texels_;
    mutable std::mutex mutex_;
    mutable std::vector<bool> baked_; // per tile, under mutex_
    mutable int tilesBaked_ = 0;      // under mutex_
};

} // namespace lumar
