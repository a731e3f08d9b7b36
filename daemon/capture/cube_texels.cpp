#include "capture/cube_texels.h"

namespace lumar {

CubeTexels::CubeTexels(const EnvironmentCube& cube, float exposure, const SrgbEncoder& encoder)
    : cube_(cube), exposure_(exposure), encoder_(encoder), texels_(allocateSparsePacked(cube.texelCount())),
      baked_(size_t(cube.tileCount()), false)
{
}

template <typename Needed> void CubeTexels::bakeWhere(Needed needed) const
{
    // Baking under the lock: a frame's new tiles take a few ms at most (the first frame's,
    // about 130 of 6144 at 720p, ~4 ms), and a second thread needing the same tiles has to
    // wait for them anyway.
    const std::lock_guard lock(mutex_);
    for (int tile = 0; tile < cube_.tileCount(); ++tile) {
        if (!baked_[size_t(tile)] && needed(tile)) {
            cube_.bakeTile(tile, exposure_, encoder_, texels_.get());
            baked_[size_t(tile)] = true;
            ++tilesBaked_;
        }
    }
}

void CubeTexels::prepare(const ViewCone& view) const
{
    bakeWhere([&](int tile) { return cube_.tileMayBeSeen(tile, view); });
}

void CubeTexels::prepareAll() const
{
    bakeWhere([](int) { return true; });
}

int CubeTexels::tilesBaked() const
{
    const std::lock_guard lock(mutex_);
    return tilesBaked_;
}

} // namespace lumar
