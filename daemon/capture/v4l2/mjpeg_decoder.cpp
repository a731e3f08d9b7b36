#include "capture/v4l2/mjpeg_decoder.h"

#include <algorithm>
#include <cstring>

#include <turbojpeg.h>

#include "core/error.h"

namespace lumar {

void MjpegDecoder::HandleDeleter::operator()(void* handle) const
{
    tjDestroy(static_cast<tjhandle>(handle));
}

MjpegDecoder::MjpegDecoder() : handle_(tjInitDecompress())
{
    if (!handle_) {
        throw RuntimeError(std::string("libturbojpeg: cannot create a decompressor: ") + tjGetErrorStr2(nullptr));
    }
}

bool MjpegDecoder::decode(const uint8_t* jpeg, size_t size, int width, int height, Image8& rgb, Image8& luma,
                          std::string& error)
{
    auto* handle = static_cast<tjhandle>(handle_.get());
    if (size < 4 || jpeg[0] != 0xFF || jpeg[1] != 0xD8) {
        error = "no JPEG start-of-image marker";
        return false;
    }
    int jpegWidth = 0;
    int jpegHeight = 0;
    int subsampling = 0;
    int colourspace = 0;
    if (tjDecompressHeader3(handle, jpeg, static_cast<unsigned long>(size), &jpegWidth, &jpegHeight, &subsampling,
                            &colourspace) != 0) {
        error = tjGetErrorStr2(handle);
        return false;
    }
    if (jpegWidth != width || jpegHeight != height) {
        error = "decodes to " + std::to_string(jpegWidth) + "x" + std::to_string(jpegHeight) + ", negotiated " +
                std::to_string(width) + "x" + std::to_string(height);
        return false;
    }
    rgb.reshape(width, height, 3);
    luma.reshape(width, height, 1);
    // A warning (a truncated scan, a corrupt Huffman code) stops the decode: the frame is
    // dropped rather than shown half grey.
    const int flags = TJFLAG_STOPONWARNING;
    if (subsampling == TJSAMP_GRAY) {
        if (tjDecompress2(handle, jpeg, static_cast<unsigned long>(size), luma.data.data(), width, width, height,
                          TJPF_GRAY, flags) != 0) {
            error = tjGetErrorStr2(handle);
            return false;
        }
        for (size_t i = 0, n = luma.data.size(); i < n; ++i) {
            std::memset(rgb.data.data() + 3 * i, luma.data[i], 3);
        }
        return true;
    }
    if (colourspace != TJCS_YCbCr) {
        error = "unsupported JPEG colour space " + std::to_string(colourspace);
        return false;
    }
    // The Y plane goes straight into the luma image when libturbojpeg's plane has no padding
    // (even sizes, as cameras send); otherwise through a scratch plane.
    const int yWidth = tjPlaneWidth(0, width, subsampling);
    const int yHeight = tjPlaneHeight(0, height, subsampling);
    const int cWidth = tjPlaneWidth(1, width, subsampling);
    const int cHeight = tjPlaneHeight(1, height, subsampling);
    if (yWidth <= 0 || yHeight <= 0 || cWidth <= 0 || cHeight <= 0) {
        error = "unsupported JPEG subsampling " + std::to_string(subsampling);
        return false;
    }
    const bool direct = yWidth == width && yHeight == height;
    if (!direct) {
        lumaScratch_.resize(size_t(yWidth) * size_t(yHeight));
    }
    chroma_.resize(2 * size_t(cWidth) * size_t(cHeight));
    unsigned char* planes[3] = {direct ? luma.data.data() : lumaScratch_.data(), chroma_.data(),
                                chroma_.data() + size_t(cWidth) * size_t(cHeight)};
    int strides[3] = {yWidth, cWidth, cWidth};
    if (tjDecompressToYUVPlanes(handle, jpeg, static_cast<unsigned long>(size), planes, width, strides, height,
                                flags) != 0) {
        error = tjGetErrorStr2(handle);
        return false;
    }
    const unsigned char* constPlanes[3] = {planes[0], planes[1], planes[2]};
    if (tjDecodeYUVPlanes(handle, constPlanes, strides, subsampling, rgb.data.data(), width, width * 3, height,
                          TJPF_RGB, 0) != 0) {
        error = tjGetErrorStr2(handle);
        return false;
    }
    if (!direct) {
        for (int row = 0; row < height; ++row) {
            std::memcpy(luma.row(row), lumaScratch_.data() + size_t(row) * size_t(yWidth), size_t(width));
        }
    }
    return true;
}

} // namespace lumar
