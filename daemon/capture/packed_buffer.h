// Large buffers of packed code values (the lit table, the environment cube), allocated
// without zero-filling and, where the kernel offers transparent huge pages on request, in
// 2 MiB pages: the buffers are written whole right away, and first-touch page faults were
// the largest cost of baking them (the 1024² cube, 25 MB: 207–224 ms of CPU with the hint,
// 310–326 ms without, three alternating runs each on a loaded 2-core VM).
#pragma once

#include <cstddef>
#include <cstdlib>
#include <memory>
#include <new>

#include <sys/mman.h>

#include "capture/fake_scene_shading.h"

namespace lumar {

struct FreeDeleter {
    void operator()(void* p) const { std::free(p); }
};
using PackedBuffer = std::unique_ptr<fake_scene::PackedRgb[], FreeDeleter>;

inline PackedBuffer allocatePacked(size_t count)
{
    constexpr size_t kHugePage = size_t(2) << 20;
    const size_t bytes = (count * sizeof(fake_scene::PackedRgb) + kHugePage - 1) / kHugePage * kHugePage;
    void* p = std::aligned_alloc(kHugePage, bytes);
    if (p == nullptr) {
        throw std::bad_alloc();
    }
    (void)madvise(p, bytes, MADV_HUGEPAGE); // a hint: without it the pages are just smaller
    return PackedBuffer(static_cast<fake_scene::PackedRgb*>(p));
}

// A buffer filled piecewise, where parts may never be needed (the environment cube's tiles):
// anonymous pages of 4 KiB that become resident when first written and read as zeros until
// then; never huge pages, whose first write would make 2 MiB resident at once.
struct Unmapper {
    size_t bytes = 0;
    void operator()(fake_scene::PackedRgb* p) const { (void)munmap(p, bytes); }
};
using SparsePackedBuffer = std::unique_ptr<fake_scene::PackedRgb[], Unmapper>;

inline SparsePackedBuffer allocateSparsePacked(size_t count)
{
    const size_t bytes = count * sizeof(fake_scene::PackedRgb);
    void* p = mmap(nullptr, bytes, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
    if (p == MAP_FAILED) {
        throw std::bad_alloc();
    }
    (void)madvise(p, bytes, MADV_NOHUGEPAGE); // where the kernel would use them unasked
    return SparsePackedBuffer(static_cast<fake_scene::PackedRgb*>(p), Unmapper{bytes});
}

} // namespace lumar
