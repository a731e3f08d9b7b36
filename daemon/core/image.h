// Plain CPU images. Pixels are tightly packed, row-major, row 0 at the top (as a camera
// and a PNG store them), channels interleaved.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

namespace lumar {

template <typename T> struct Image {
    int width = 0;
    int height = 0;
    int channels = 0;
    std::vector<T> data;

    Image() = default;
    Image(int w, int h, int c) : width(w), height(h), channels(c), data(size_t(w) * size_t(h) * size_t(c)) {}

    // Resizes only when the shape changes, so a buffer reused every frame never reallocates.
    void reshape(int w, int h, int c)
    {
        width = w;
        height = h;
        channels = c;
        data.resize(size_t(w) * size_t(h) * size_t(c));
    }
    [[nodiscard]] bool empty() const { return data.empty(); }
    [[nodiscard]] size_t rowElements() const { return size_t(width) * size_t(channels); }
    T* row(int y) { return data.data() + size_t(y) * rowElements(); }
    const T* row(int y) const { return data.data() + size_t(y) * rowElements(); }
    T* at(int x, int y) { return row(y) + size_t(x) * size_t(channels); }
    const T* at(int x, int y) const { return row(y) + size_t(x) * size_t(channels); }
};

using Image8 = Image<uint8_t>; // sRGB-encoded colour (3 or 4 channels) or 8-bit luma (1)
using ImageF = Image<float>;   // linear HDR radiance (3 channels)

} // namespace lumar
