// A camera frame kept in its YCbCr layout (NV12 or YUYV) with the colorimetry the driver
// reported, so the renderer can upload (or import) the planes and convert on the GPU instead
// of the capture thread converting every pixel on the CPU.
#pragma once

#include <array>
#include <atomic>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <memory>
#include <vector>

namespace lumar {

// Copies `rows` rows of `rowBytes` from `data` (rows `stride` bytes apart) into `plane`,
// tightly packed: a camera buffer's padding dropped.
inline void copyPlaneRows(const uint8_t* data, size_t stride, size_t rowBytes, int rows, std::vector<uint8_t>& plane)
{
    plane.resize(rowBytes * size_t(rows));
    for (int row = 0; row < rows; ++row)
        std::memcpy(plane.data() + rowBytes * size_t(row), data + stride * size_t(row), rowBytes);
}

enum class YCbCrMatrix { Bt601, Bt709 };

struct YCbCrColorimetry {
    YCbCrMatrix matrix = YCbCrMatrix::Bt601;
    bool fullRange = false; // false: Y in [16, 235], Cb/Cr in [16, 240]
};

enum class YCbCrLayout {
    None, // no raw frame: the RGB image is the frame
    Nv12, // plane 0: Y, width x height; plane 1: Cb Cr pairs, width/2 pairs x height/2 rows
    Yuyv, // plane 0: Y0 Cb Y1 Cr per two pixels, width/2 groups x height rows; plane 1 unused
};

// A camera buffer lent to frames instead of copied out of (zero-copy capture): its planes as
// the CPU sees them (for a plain texture upload and the tracker) and, where the driver
// exported it (VIDIOC_EXPBUF), as a dmabuf the GPU can import. The capture source makes one
// per driver buffer for the stream's life and owns the mapping and the dmabuf through it; a
// frame showing the buffer holds a shared_ptr to it, and the source gives the buffer back to
// the driver only once it holds the last reference again (so holding one costs no allocation
// per frame, and the memory stays valid for as long as any frame shows it).
class CameraBuffer {
public:
    struct Plane {
        const uint8_t* data = nullptr; // the mapping, valid while this object lives
        size_t size = 0;               // bytes readable from data
        int dmabufFd = -1;             // owned by this object; -1: not exported
        uint32_t offset = 0;           // of the plane within the dmabuf
    };

    virtual ~CameraBuffer() = default;
    CameraBuffer(const CameraBuffer&) = delete;
    CameraBuffer& operator=(const CameraBuffer&) = delete;

    [[nodiscard]] uint64_t id() const { return id_; }               // unique in the process, for import caches
    [[nodiscard]] uint32_t drmFourcc() const { return drmFourcc_; } // DRM_FORMAT_NV12/_YUYV; 0: none
    [[nodiscard]] const std::array<Plane, 2>& planes() const { return planes_; }
    [[nodiscard]] bool exported() const { return drmFourcc_ != 0 && planes_[0].dmabufFd >= 0; }

protected:
    CameraBuffer() : id_(nextId()) {}
    std::array<Plane, 2> planes_{}; // plane 1 unused for YUYV
    uint32_t drmFourcc_ = 0;

private:
    static uint64_t nextId()
    {
        static std::atomic<uint64_t> next{1};
        return next.fetch_add(1, std::memory_order_relaxed);
    }

    uint64_t id_;
};

struct YCbCrImage {
    YCbCrLayout layout = YCbCrLayout::None;
    int width = 0; // pixels (even)
    int height = 0;
    YCbCrColorimetry colorimetry;
    // Owned copies, reused from frame to frame; strides in bytes.
    std::vector<uint8_t> plane0;
    std::vector<uint8_t> plane1;
    size_t stride0 = 0;
    size_t stride1 = 0;
    // Zero-copy frames: the planes are read from this lent camera buffer (with stride0 and
    // stride1) instead of plane0 and plane1, which stay empty. Null for copied frames.
    std::shared_ptr<const CameraBuffer> buffer;

    [[nodiscard]] bool empty() const { return layout == YCbCrLayout::None; }
    // Plane `index` (0 or 1) wherever it lives, and how many bytes of it may be read.
    [[nodiscard]] const uint8_t* planeData(int index) const
    {
        return buffer ? buffer->planes()[size_t(index)].data : (index == 0 ? plane0 : plane1).data();
    }
    [[nodiscard]] size_t planeSize(int index) const
    {
        return buffer ? buffer->planes()[size_t(index)].size : (index == 0 ? plane0 : plane1).size();
    }
};

} // namespace lumar
