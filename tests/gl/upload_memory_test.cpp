// What uploading a model holds in the program's own memory at its peak. The stand-in levels
// need only geometry: each once took a copy of the whole model, decoded textures included,
// which for CesiumMilkTruck's 2048² image raised the car scene's resident peak at load from
// ~178 to ~190 MB on llvmpipe (issue 18). Counted here with a global operator new that tracks
// live bytes (llvmpipe's texture storage is malloc'ed by Mesa and not counted; LLVM's C++ is).
#include <atomic>
#include <cstdlib>
#include <new>

#include <gtest/gtest.h>
#include <malloc.h>

#include "gl_test_support.h"
#include "gles_renderer/assets/builtin_shapes.h"
#include "gles_renderer/gl/frame_readback.h"
#include "gles_renderer/gl/render_target.h"
#include "gles_renderer/scene/gpu_model.h"

namespace {

std::atomic<size_t> gLiveBytes{0};
std::atomic<size_t> gPeakBytes{0};

// nullptr when malloc fails (the nothrow forms return it, the others throw).
void* countedAllocationOrNull(size_t size) noexcept
{
    void* p = std::malloc(size == 0 ? 1 : size);
    if (!p)
        return nullptr;
    const size_t live = gLiveBytes.fetch_add(malloc_usable_size(p)) + malloc_usable_size(p);
    size_t peak = gPeakBytes.load();
    while (live > peak && !gPeakBytes.compare_exchange_weak(peak, live)) {
    }
    return p;
}

void* countedAllocation(size_t size)
{
    void* p = countedAllocationOrNull(size);
    if (!p)
        throw std::bad_alloc();
    return p;
}

void countedRelease(void* p) noexcept
{
    if (!p)
        return;
    gLiveBytes.fetch_sub(malloc_usable_size(p));
    std::free(p);
}

} // namespace

void* operator new(size_t size)
{
    return countedAllocation(size);
}
void* operator new[](size_t size)
{
    return countedAllocation(size);
}
void operator delete(void* p) noexcept
{
    countedRelease(p);
}
void operator delete[](void* p) noexcept
{
    countedRelease(p);
}
void operator delete(void* p, size_t) noexcept
{
    countedRelease(p);
}
void operator delete[](void* p, size_t) noexcept
{
    countedRelease(p);
}
// The nothrow forms too: LLVM uses them, and under AddressSanitizer, which replaces every form
// the program does not, its new paired with the delete above was an alloc-dealloc mismatch.
void* operator new(size_t size, const std::nothrow_t&) noexcept
{
    return countedAllocationOrNull(size);
}
void* operator new[](size_t size, const std::nothrow_t&) noexcept
{
    return countedAllocationOrNull(size);
}
void operator delete(void* p, const std::nothrow_t&) noexcept
{
    countedRelease(p);
}
void operator delete[](void* p, const std::nothrow_t&) noexcept
{
    countedRelease(p);
}

namespace lumar {
namespace {

TEST(UploadMemory, TheStandInsCopyNeitherTexturesNorMaterials)
{
    LUMAR_RENDERER_OR_SKIP(renderer, 16, 16); // for its GL context
    (void)renderer;
    const DefaultTextures defaults = makeDefaultTextures();
    // A dense mesh (stand-ins are simplified from it) with a 1024² base colour: 4 MiB.
    GltfModel model = makeUvSphere(64, 32);
    GltfTexture texture;
    texture.image = Image8(1024, 1024, 4);
    texture.srgb = true;
    model.textures.push_back(std::move(texture));
    model.materials[0].baseColorTexture = 0;
    const size_t textureBytes = model.textures[0].image.data.size();

    // Once first: Mesa's mipmap generation compiles its shaders with LLVM, whose C++ allocations
    // this operator new counts too.
    (void)uploadModel(model, defaults);
    gPeakBytes.store(gLiveBytes.load());
    const size_t before = gLiveBytes.load();
    const GpuModel gpu = uploadModel(model, defaults);
    const size_t peak = gPeakBytes.load() - before;

    ASSERT_GE(gpu.proxyLevels.size(), 2U) << "the sphere should have simplified stand-ins";
    // The mesh's own copies (interleaved vertices, simplified indices) are tens of KB; one copy
    // of the texture would be 4 MiB.
    EXPECT_LT(peak, textureBytes / 4) << "uploading held " << peak << " bytes at its peak";
}

// Reading a frame back stages RGBA (GLES guarantees no RGB reads; llvmpipe offers none) a strip
// of rows at a time: a whole-frame staging copy stayed resident, 3.5 MB at 1280x720 (issue 18).
TEST(UploadMemory, FrameReadbackStagesAStripNotAFrame)
{
    LUMAR_RENDERER_OR_SKIP(renderer, 16, 16); // for its GL context
    (void)renderer;
    constexpr int kWidth = 1280, kHeight = 720;
    const RenderTarget target(kWidth, kHeight, 1);
    target.bindForDrawing();
    glClearColor(0.25f, 0.5f, 0.75f, 1.0f);
    glClear(GL_COLOR_BUFFER_BIT);
    target.finishFrame();
    Image8 rgb(kWidth, kHeight, 3);
    // Once first, for whatever Mesa's first read compiles with LLVM (counted here too).
    FrameReadback(target.readFramebuffer(), kWidth, kHeight).read(rgb);

    gPeakBytes.store(gLiveBytes.load());
    const size_t before = gLiveBytes.load();
    FrameReadback readback(target.readFramebuffer(), kWidth, kHeight);
    readback.read(rgb);
    const size_t peak = gPeakBytes.load() - before;

    const size_t frameRgbaBytes = size_t(kWidth) * kHeight * 4;
    EXPECT_LT(peak, frameRgbaBytes / 4) << "reading back held " << peak << " bytes at its peak";
    // And it read the whole frame, the last strip included.
    for (const size_t pixel : {size_t(0), size_t(kWidth) * (kHeight - 1) + kWidth - 1}) {
        EXPECT_NEAR(rgb.data[pixel * 3 + 0], 64, 1);
        EXPECT_NEAR(rgb.data[pixel * 3 + 1], 128, 1);
        EXPECT_NEAR(rgb.data[pixel * 3 + 2], 191, 1);
    }
}

} // namespace
} // namespace lumar
