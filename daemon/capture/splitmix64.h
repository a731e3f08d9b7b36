// SplitMix64: a tiny, fast, well-mixed 64-bit generator. Used where the fake camera needs
// reproducible randomness (the table's texture, sensor noise); `mix` also hashes seeds.
#pragma once

#include <cstdint>

namespace lumar {

// The SplitMix64 output function: a bijective 64-bit hash.
inline uint64_t splitMix64Hash(uint64_t z)
{
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
    return z ^ (z >> 31);
}

struct SplitMix64 {
    uint64_t state = 0;

    uint64_t next()
    {
        state += 0x9e3779b97f4a7c15ULL;
        return splitMix64Hash(state);
    }
    // Uniform in [0, 1) with 53 random bits.
    double uniform() { return double(next() >> 11) * (1.0 / 9007199254740992.0); }
};

} // namespace lumar
