#include "capture/lazy_texels.h"

#include <utility>

namespace lumar {

LazyTexels::LazyTexels(size_t texelCount, int tileCount, BakeTile bakeTile)
    : bakeTile_(std::move(bakeTile)), texels_(allocateSparsePacked(texelCount)), baked_(size_t(tileCount), false)
{
}

int LazyTexels::tilesBaked() const
{
    const std::lock_guard lock(mutex_);
    return tilesBaked_;
}

} // namespace lumar
