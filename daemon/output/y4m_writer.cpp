#include "output/y4m_writer.h"

#include <algorithm>
#include <cmath>
#include <numeric>

#include "core/error.h"
#include "core/log.h"

namespace lumar {
namespace {

uint8_t clampToByte(double v)
{
    return uint8_t(std::clamp(std::lround(v), 0L, 255L));
}

} // namespace

std::string y4mFrameRate(double fps)
{
    if (!(fps > 0.0) || !std::isfinite(fps) || fps > 1e6) {
        throw InputError("output: frame rate must be positive, got " + std::to_string(fps));
    }
    const double whole = std::round(fps);
    if (std::abs(fps - whole) < 1e-9 * fps) {
        return std::to_string(int64_t(whole)) + ":1";
    }
    // 29.97, 59.94, 23.976 are n × 1000/1001.
    const double ntsc = fps * 1001.0 / 1000.0;
    if (std::abs(ntsc - std::round(ntsc)) < 1e-6) {
        return std::to_string(int64_t(std::round(ntsc)) * 1000) + ":1001";
    }
    int64_t numerator = std::llround(fps * 1000.0);
    int64_t denominator = 1000;
    const int64_t divisor = std::gcd(numerator, denominator);
    numerator /= divisor;
    denominator /= divisor;
    return std::to_string(numerator) + ":" + std::to_string(denominator);
}

Y4mWriter::Y4mWriter(const std::filesystem::path& file, double fps)
    : path_(file), frameRate_(y4mFrameRate(fps)), file_(openForWriting(file))
{
}

Y4mWriter::~Y4mWriter()
{
    try {
        finish();
    } catch (const std::exception& e) {
        LUMAR_LOG(Output, Error) << e.what();
    }
}

void Y4mWriter::write(const Image8& rgb)
{
    if (!file_) {
        throw RuntimeError(path_.string() + ": write after finish");
    }
    if (rgb.channels != 3 || rgb.width <= 0 || rgb.height <= 0) {
        throw InputError(path_.string() + ": expected a non-empty 3-channel image");
    }
    if (width_ == 0) {
        if (rgb.width % 2 != 0 || rgb.height % 2 != 0) {
            throw InputError(path_.string() + ": 4:2:0 video needs an even width and height, got " +
                             std::to_string(rgb.width) + "x" + std::to_string(rgb.height));
        }
        width_ = rgb.width;
        height_ = rgb.height;
        const std::string header = "YUV4MPEG2 W" + std::to_string(width_) + " H" + std::to_string(height_) + " F" +
                                   frameRate_ + " Ip A1:1 C420jpeg XCOLORRANGE=FULL\n";
        writeAll(file_.get(), header.data(), header.size(), path_);
        planes_.resize(size_t(width_) * size_t(height_) * 3 / 2);
    } else if (rgb.width != width_ || rgb.height != height_) {
        throw InputError(path_.string() + ": frame size changed from " + std::to_string(width_) + "x" +
                         std::to_string(height_) + " to " + std::to_string(rgb.width) + "x" +
                         std::to_string(rgb.height));
    }

    // Full-range BT.601: Y = 0.299 R + 0.587 G + 0.114 B, Cb = 128 + (B − Y) / 1.772,
    // Cr = 128 + (R − Y) / 1.402; chroma is the mean over each 2 × 2 block (centred siting,
    // as C420jpeg states).
    const size_t lumaBytes = size_t(width_) * size_t(height_);
    const size_t chromaWidth = size_t(width_ / 2);
    uint8_t* yPlane = planes_.data();
    uint8_t* cbPlane = yPlane + lumaBytes;
    uint8_t* crPlane = cbPlane + lumaBytes / 4;
    for (int y = 0; y < height_; y += 2) {
        const uint8_t* rows[2] = {rgb.row(y), rgb.row(y + 1)};
        for (int x = 0; x < width_; x += 2) {
            double cbSum = 0.0;
            double crSum = 0.0;
            for (int dy = 0; dy < 2; ++dy) {
                for (int dx = 0; dx < 2; ++dx) {
                    const uint8_t* p = rows[dy] + 3 * (x + dx);
                    const double luma = 0.299 * p[0] + 0.587 * p[1] + 0.114 * p[2];
                    yPlane[size_t(y + dy) * size_t(width_) + size_t(x + dx)] = clampToByte(luma);
                    cbSum += (p[2] - luma) / 1.772;
                    crSum += (p[0] - luma) / 1.402;
                }
            }
            const size_t c = size_t(y / 2) * chromaWidth + size_t(x / 2);
            cbPlane[c] = clampToByte(128.0 + 0.25 * cbSum);
            crPlane[c] = clampToByte(128.0 + 0.25 * crSum);
        }
    }
    static constexpr char kFrameLine[] = "FRAME\n";
    writeAll(file_.get(), kFrameLine, sizeof(kFrameLine) - 1, path_);
    writeAll(file_.get(), planes_.data(), planes_.size(), path_);
}

void Y4mWriter::finish()
{
    if (file_ && width_ == 0) {
        LUMAR_LOG(Output, Warn) << path_.string() << ": no frame was written, the video is empty";
    }
    closeChecked(file_, path_);
}

} // namespace lumar
