// Our CPU YCbCr → RGB conversions against libyuv's, per layout, matrix and range: time per
// frame (interleaved rounds, medians) and error against the exact formula in double precision
// (max and mean |error| and the mean signed error per channel, in code values). The figures
// behind the choice of path in daemon/capture/v4l2/ycbcr_to_rgb.cpp and
// daemon/capture/colour_conversion.cpp. Not a test.
//
//   build/tests/tools/ycbcr_conversion_bench [rounds] [repetitions] [times]
//
// (defaults 5 rounds of 20 frames; "times" skips the error sweeps.)
//
// libyuv's candidates write R, G, B bytes (its "RAW"): the NV21/I422 functions given the
// planes with U and V swapped and the swapped-constant tables (kYvu…), as libyuv's own
// NV12ToRAWMatrix macro does. YUYV has no matrix-parameterised libyuv converter, so its
// candidate splits each row (YUY2ToI422, the Y straight into the luma plane) and converts the
// planes (I422ToRGB24Matrix); GREY's expands Y into ARGB (I400ToARGBMatrix) and packs it
// (ARGBToRAW). Luma: libyuv has no range expansion, so its limited-range candidates add ours.
#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include <libyuv.h>

#include "capture/colour_conversion.h"
#include "capture/v4l2/ycbcr_to_rgb.h"

namespace {

using lumar::Image8;
using lumar::YCbCrColorimetry;
using lumar::YCbCrMatrix;

enum class Layout { Nv12, Yuyv, Grey, Y4m420 };

const char* layoutName(Layout layout)
{
    switch (layout) {
    case Layout::Nv12:
        return "NV12";
    case Layout::Yuyv:
        return "YUYV";
    case Layout::Grey:
        return "GREY";
    case Layout::Y4m420:
        return "Y4M 420";
    }
    return "?";
}

std::string colorimetryName(YCbCrColorimetry c)
{
    return std::string(c.matrix == YCbCrMatrix::Bt709 ? "709" : "601") + (c.fullRange ? " full" : " limited");
}

const libyuv::YuvConstants* swappedConstants(YCbCrColorimetry c)
{
    if (c.matrix == YCbCrMatrix::Bt709)
        return c.fullRange ? &libyuv::kYvuF709Constants : &libyuv::kYvuH709Constants;
    return c.fullRange ? &libyuv::kYvuJPEGConstants : &libyuv::kYvuI601Constants;
}

const libyuv::YuvConstants* constants(YCbCrColorimetry c)
{
    if (c.matrix == YCbCrMatrix::Bt709)
        return c.fullRange ? &libyuv::kYuvF709Constants : &libyuv::kYuvH709Constants;
    return c.fullRange ? &libyuv::kYuvJPEGConstants : &libyuv::kYuvI601Constants;
}

// The exact conversion of one sample: (Y, Cb, Cr) may be fractional (interpolated chroma).
std::array<double, 3> exactRgb(YCbCrColorimetry c, double y, double cb, double cr)
{
    const double kr = c.matrix == YCbCrMatrix::Bt709 ? 0.2126 : 0.299;
    const double kb = c.matrix == YCbCrMatrix::Bt709 ? 0.0722 : 0.114;
    const double kg = 1.0 - kr - kb;
    const double yv = c.fullRange ? y : (y - 16.0) * 255.0 / 219.0;
    const double cs = c.fullRange ? 1.0 : 255.0 / 224.0;
    const double u = (cb - 128.0) * cs;
    const double v = (cr - 128.0) * cs;
    const std::array<double, 3> rgb{yv + 2.0 * (1.0 - kr) * v,
                                    yv - 2.0 * (1.0 - kb) * kb / kg * u - 2.0 * (1.0 - kr) * kr / kg * v,
                                    yv + 2.0 * (1.0 - kb) * u};
    return {std::clamp(rgb[0], 0.0, 255.0), std::clamp(rgb[1], 0.0, 255.0), std::clamp(rgb[2], 0.0, 255.0)};
}

// One picture in a layout, tightly packed (NV12: UV rows after the Y rows; Y4M: Y, Cb, Cr planes).
struct Picture {
    Layout layout;
    int width;
    int height;
    std::vector<uint8_t> bytes;

    [[nodiscard]] size_t yStride() const { return size_t(width) * (layout == Layout::Yuyv ? 2 : 1); }
    [[nodiscard]] const uint8_t* chroma() const { return bytes.data() + size_t(width) * size_t(height); }
    // (Y, Cb, Cr) at a pixel, chroma as our NV12/YUYV converters read it (replicated).
    [[nodiscard]] std::array<int, 3> sample(int x, int y) const
    {
        const uint8_t* p = bytes.data();
        switch (layout) {
        case Layout::Nv12: {
            const uint8_t* uv = chroma() + size_t(y / 2) * size_t(width) + size_t(x / 2) * 2;
            return {p[size_t(y) * size_t(width) + size_t(x)], uv[0], uv[1]};
        }
        case Layout::Yuyv: {
            const uint8_t* pair = p + size_t(y) * yStride() + size_t(x / 2) * 4;
            return {pair[(x % 2) * 2], pair[1], pair[3]};
        }
        default:
            return {p[size_t(y) * size_t(width) + size_t(x)], 128, 128};
        }
    }
};

size_t pictureBytes(Layout layout, int width, int height)
{
    const size_t pixels = size_t(width) * size_t(height);
    switch (layout) {
    case Layout::Nv12:
    case Layout::Y4m420:
        return pixels * 3 / 2;
    case Layout::Yuyv:
        return pixels * 2;
    case Layout::Grey:
        return pixels;
    }
    return 0;
}

Picture randomPicture(Layout layout, int width, int height, unsigned seed, bool legalOnly, bool fullRange)
{
    Picture picture{layout, width, height, std::vector<uint8_t>(pictureBytes(layout, width, height))};
    std::mt19937 engine(seed);
    // Luma bytes of limited-range legal pictures in [16, 235], chroma in [16, 240].
    const bool limited = legalOnly && !fullRange;
    std::uniform_int_distribution<int> luma(limited ? 16 : 0, limited ? 235 : 255);
    std::uniform_int_distribution<int> chroma(limited ? 16 : 0, limited ? 240 : 255);
    const size_t lumaBytes = size_t(width) * size_t(height);
    for (size_t i = 0; i < picture.bytes.size(); ++i) {
        bool isLuma = i < lumaBytes;
        if (layout == Layout::Yuyv)
            isLuma = i % 2 == 0;
        picture.bytes[i] = uint8_t(isLuma ? luma(engine) : chroma(engine));
    }
    return picture;
}

// Every (Y, Cb, Cr) byte triple once (NV12/YUYV; GREY: every Y), limited to the legal
// code values where `legalOnly` and the range is limited.
std::vector<Picture> exhaustivePictures(Layout layout, YCbCrColorimetry c, bool legalOnly)
{
    const bool limited = legalOnly && !c.fullRange;
    const int yLo = limited ? 16 : 0;
    const int yHi = limited ? 235 : 255;
    const int cLo = limited ? 16 : 0;
    const int cHi = limited ? 240 : 255;
    const int cCount = cHi - cLo + 1;
    std::vector<Picture> pictures;
    if (layout == Layout::Grey) {
        Picture p{layout, 256, 2, std::vector<uint8_t>(512)};
        for (int i = 0; i < 512; ++i)
            p.bytes[size_t(i)] = uint8_t(std::clamp(i % 256, yLo, yHi));
        pictures.push_back(p);
        return pictures;
    }
    // One chroma sample per (Cb, Cr) pair; the Y values it covers step through [yLo, yHi],
    // four (NV12: 2 x 2) or two (YUYV) per picture.
    const int perPicture = layout == Layout::Nv12 ? 4 : 2;
    for (int y0 = yLo; y0 <= yHi; y0 += perPicture) {
        auto yAt = [&](int k) { return uint8_t(std::min(y0 + k, yHi)); };
        if (layout == Layout::Nv12) {
            Picture p{layout, 2 * cCount, 2 * cCount, {}};
            p.bytes.resize(pictureBytes(layout, p.width, p.height));
            for (int row = 0; row < p.height; ++row)
                for (int col = 0; col < p.width; ++col)
                    p.bytes[size_t(row) * size_t(p.width) + size_t(col)] = yAt((row % 2) * 2 + col % 2);
            uint8_t* uv = p.bytes.data() + size_t(p.width) * size_t(p.height);
            for (int row = 0; row < cCount; ++row)
                for (int col = 0; col < cCount; ++col) {
                    uv[size_t(row) * size_t(p.width) + size_t(col) * 2] = uint8_t(cLo + col);
                    uv[size_t(row) * size_t(p.width) + size_t(col) * 2 + 1] = uint8_t(cLo + row);
                }
            pictures.push_back(std::move(p));
        } else {
            Picture p{layout, 2 * cCount, cCount, {}};
            p.bytes.resize(pictureBytes(layout, p.width, p.height));
            for (int row = 0; row < cCount; ++row)
                for (int col = 0; col < cCount; ++col) {
                    uint8_t* q = p.bytes.data() + size_t(row) * p.yStride() + size_t(col) * 4;
                    q[0] = yAt(0);
                    q[1] = uint8_t(cLo + col);
                    q[2] = yAt(1);
                    q[3] = uint8_t(cLo + row);
                }
            pictures.push_back(std::move(p));
        }
    }
    return pictures;
}

using Convert = std::function<void(const Picture&, Image8& rgb, Image8& luma)>;

// Ours: the daemon's converters as they are.
Convert ours(Layout layout, YCbCrColorimetry c)
{
    if (layout == Layout::Y4m420) {
        // Its taps are per size: made again when the size changes (not while timing).
        auto state = std::make_shared<std::pair<std::array<int, 2>, std::unique_ptr<lumar::YCbCrToRgb>>>();
        return [c, state](const Picture& p, Image8& rgb, Image8& luma) {
            auto& [size, converter] = *state;
            if (!converter || size != std::array<int, 2>{p.width, p.height}) {
                size = {p.width, p.height};
                converter =
                    std::make_unique<lumar::YCbCrToRgb>(p.width, p.height, (p.width + 1) / 2, (p.height + 1) / 2);
            }
            lumar::PlanarYCbCr planes;
            planes.y = p.bytes.data();
            planes.cb = p.chroma();
            planes.cr = planes.cb + size_t((p.width + 1) / 2) * size_t((p.height + 1) / 2);
            planes.fullRange = c.fullRange;
            converter->convert(planes, rgb, luma);
        };
    }
    return [layout, converter = lumar::YCbCrConverter(c)](const Picture& p, Image8& rgb, Image8& luma) {
        if (layout == Layout::Nv12)
            converter.convertNv12(p.bytes.data(), p.yStride(), p.chroma(), p.yStride(), p.width, p.height, rgb, luma);
        else if (layout == Layout::Yuyv)
            converter.convertYuyv(p.bytes.data(), p.yStride(), p.width, p.height, rgb, luma);
        else
            converter.convertGrey(p.bytes.data(), p.yStride(), p.width, p.height, rgb, luma);
    };
}

// libyuv's candidate, luma included (ours where the range needs expanding).
Convert libyuvCandidate(Layout layout, YCbCrColorimetry c)
{
    return [layout, c, lumaConverter = lumar::YCbCrConverter(c)](const Picture& p, Image8& rgb, Image8& luma) {
        const int w = p.width;
        const int h = p.height;
        rgb.reshape(w, h, 3);
        luma.reshape(w, h, 1);
        const int rgbStride = w * 3;
        switch (layout) {
        case Layout::Nv12:
            libyuv::NV21ToRGB24Matrix(p.bytes.data(), w, p.chroma(), w, rgb.data.data(), rgbStride, swappedConstants(c),
                                      w, h);
            if (c.fullRange)
                libyuv::CopyPlane(p.bytes.data(), w, luma.data.data(), w, w, h);
            else
                lumaConverter.convertLuma(p.bytes.data(), p.yStride(), 1, w, h, luma);
            break;
        case Layout::Yuyv: {
            std::vector<uint8_t> u(size_t(w / 2));
            std::vector<uint8_t> v(size_t(w / 2));
            std::vector<uint8_t> y(static_cast<size_t>(w));
            for (int row = 0; row < h; ++row) {
                const uint8_t* in = p.bytes.data() + size_t(row) * p.yStride();
                uint8_t* lumaRow = c.fullRange ? luma.row(row) : y.data();
                libyuv::YUY2ToI422(in, int(p.yStride()), lumaRow, w, u.data(), w / 2, v.data(), w / 2, w, 1);
                libyuv::I422ToRGB24Matrix(lumaRow, w, v.data(), w / 2, u.data(), w / 2, rgb.row(row), rgbStride,
                                          swappedConstants(c), w, 1);
            }
            if (!c.fullRange)
                lumaConverter.convertLuma(p.bytes.data(), p.yStride(), 2, w, h, luma);
            break;
        }
        case Layout::Grey: {
            std::vector<uint8_t> argb(size_t(w) * 4);
            for (int row = 0; row < h; ++row) {
                libyuv::I400ToARGBMatrix(p.bytes.data() + size_t(row) * size_t(w), w, argb.data(), w * 4, constants(c),
                                         w, 1);
                libyuv::ARGBToRAW(argb.data(), w * 4, rgb.row(row), rgbStride, w, 1);
            }
            if (c.fullRange)
                libyuv::CopyPlane(p.bytes.data(), w, luma.data.data(), w, w, h);
            else
                lumaConverter.convertLuma(p.bytes.data(), p.yStride(), 1, w, h, luma);
            break;
        }
        case Layout::Y4m420: {
            const int cw = (w + 1) / 2;
            const uint8_t* cb = p.chroma();
            const uint8_t* cr = cb + size_t(cw) * size_t((h + 1) / 2);
            libyuv::I420ToRGB24MatrixFilter(p.bytes.data(), w, cr, cw, cb, cw, rgb.data.data(), rgbStride,
                                            swappedConstants(c), w, h, libyuv::kFilterBilinear);
            if (c.fullRange)
                libyuv::CopyPlane(p.bytes.data(), w, luma.data.data(), w, w, h);
            else
                lumaConverter.convertLuma(p.bytes.data(), size_t(w), 1, w, h, luma);
            break;
        }
        }
    };
}

struct ErrorStats {
    double worst = 0.0;
    double sumAbs = 0.0;
    std::array<double, 3> sumSigned{};
    size_t samples = 0; // pixels

    void add(const uint8_t* got, const std::array<double, 3>& exact)
    {
        for (size_t k = 0; k < 3; ++k) {
            const double d = double(got[k]) - exact[k];
            worst = std::max(worst, std::abs(d));
            sumAbs += std::abs(d);
            sumSigned[k] += d;
        }
        ++samples;
    }
    [[nodiscard]] std::string describe() const
    {
        char text[160];
        const double n = double(std::max<size_t>(samples, 1));
        std::snprintf(text, sizeof text, "max %5.2f mean %.3f bias %+.3f %+.3f %+.3f", worst, sumAbs / (3.0 * n),
                      sumSigned[0] / n, sumSigned[1] / n, sumSigned[2] / n);
        return text;
    }
};

// The exact (Y, Cb, Cr) of each output pixel of a Y4M 4:2:0 picture: chroma interpolated
// bilinearly in double precision, each sample centred on the 2 x 2 luma samples it covers.
std::array<double, 3> y4mSample(const Picture& p, int x, int y)
{
    const int cw = (p.width + 1) / 2;
    const int ch = (p.height + 1) / 2;
    auto tap = [](int i, int full, int sub, int& lo, int& hi) {
        const double pos = std::clamp((i + 0.5) * sub / full - 0.5, 0.0, double(sub - 1));
        lo = int(std::floor(pos));
        hi = std::min(lo + 1, sub - 1);
        return pos - lo;
    };
    int x0, x1, y0, y1;
    const double fx = tap(x, p.width, cw, x0, x1);
    const double fy = tap(y, p.height, ch, y0, y1);
    auto bilinear = [&](const uint8_t* plane) {
        auto at = [&](int cx, int cy) { return double(plane[size_t(cy) * size_t(cw) + size_t(cx)]); };
        const double top = at(x0, y0) + fx * (at(x1, y0) - at(x0, y0));
        const double bottom = at(x0, y1) + fx * (at(x1, y1) - at(x0, y1));
        return top + fy * (bottom - top);
    };
    const uint8_t* cb = p.chroma();
    const uint8_t* cr = cb + size_t(cw) * size_t(ch);
    return {double(p.bytes[size_t(y) * size_t(p.width) + size_t(x)]), bilinear(cb), bilinear(cr)};
}

ErrorStats accuracy(const Convert& convert, Layout layout, YCbCrColorimetry c, bool legalOnly)
{
    ErrorStats stats;
    Image8 rgb;
    Image8 luma;
    std::vector<Picture> pictures;
    if (layout == Layout::Y4m420)
        pictures.push_back(randomPicture(layout, 640, 480, 7, legalOnly, c.fullRange));
    else
        pictures = exhaustivePictures(layout, c, legalOnly);
    for (const Picture& p : pictures) {
        convert(p, rgb, luma);
        for (int y = 0; y < p.height; ++y)
            for (int x = 0; x < p.width; ++x) {
                std::array<double, 3> exact;
                if (layout == Layout::Y4m420) {
                    const auto s = y4mSample(p, x, y);
                    exact = exactRgb(c, s[0], s[1], s[2]);
                } else {
                    const auto s = p.sample(x, y);
                    exact = exactRgb(c, s[0], s[1], s[2]);
                    if (layout == Layout::Grey) // GREY: R = G = B = Y expanded, whatever the matrix
                        exact = exactRgb(c, s[0], 128.0, 128.0);
                }
                stats.add(rgb.at(x, y), exact);
            }
    }
    return stats;
}

double median(std::vector<double> values)
{
    std::sort(values.begin(), values.end());
    const size_t n = values.size();
    return n % 2 != 0 ? values[n / 2] : 0.5 * (values[n / 2 - 1] + values[n / 2]);
}

double msPerFrame(const Convert& convert, const Picture& picture, int repetitions, Image8& rgb, Image8& luma)
{
    const auto start = std::chrono::steady_clock::now();
    for (int i = 0; i < repetitions; ++i)
        convert(picture, rgb, luma);
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count() / repetitions;
}

} // namespace

int main(int argc, char** argv)
{
    const int rounds = argc > 1 ? std::max(1, std::atoi(argv[1])) : 5;
    const int repetitions = argc > 2 ? std::max(1, std::atoi(argv[2])) : 20;
    const bool errors = argc <= 3 || std::string(argv[3]) != "times";
    std::printf("# ycbcr_conversion_bench: %d interleaved rounds of %d frames, medians; errors in code values\n",
                rounds, repetitions);
    std::printf("%-8s %-12s %-9s %9s %9s %7s\n", "layout", "colorimetry", "size", "ours ms", "libyuv ms", "ratio");
    struct Size {
        int width;
        int height;
    };
    std::vector<std::string> accuracyLines;
    for (Layout layout : {Layout::Nv12, Layout::Yuyv, Layout::Grey, Layout::Y4m420}) {
        for (YCbCrMatrix matrix : {YCbCrMatrix::Bt601, YCbCrMatrix::Bt709}) {
            // GREY has no matrix; the Y4M source converts BT.601 only.
            if (matrix == YCbCrMatrix::Bt709 && (layout == Layout::Grey || layout == Layout::Y4m420))
                continue;
            for (bool fullRange : {false, true}) {
                const YCbCrColorimetry c{matrix, fullRange};
                const Convert mine = ours(layout, c);
                const Convert theirs = libyuvCandidate(layout, c);
                for (Size size : {Size{1280, 720}, Size{640, 480}}) {
                    const Picture picture = randomPicture(layout, size.width, size.height, 1, false, fullRange);
                    Image8 rgb;
                    Image8 luma;
                    mine(picture, rgb, luma); // warm-up: allocations
                    theirs(picture, rgb, luma);
                    std::vector<double> oursMs;
                    std::vector<double> theirsMs;
                    std::vector<double> ratios;
                    for (int r = 0; r < rounds; ++r) {
                        oursMs.push_back(msPerFrame(mine, picture, repetitions, rgb, luma));
                        theirsMs.push_back(msPerFrame(theirs, picture, repetitions, rgb, luma));
                        ratios.push_back(oursMs.back() / theirsMs.back());
                    }
                    std::printf("%-8s %-12s %4dx%-4d %9.3f %9.3f %6.1fx\n", layoutName(layout),
                                colorimetryName(c).c_str(), size.width, size.height, median(oursMs), median(theirsMs),
                                median(ratios));
                    std::fflush(stdout);
                }
                for (bool legalOnly : {true, false}) {
                    if (!errors || (fullRange && !legalOnly))
                        continue; // every byte is legal in full range
                    const char* inputs = legalOnly ? "legal" : "all bytes";
                    accuracyLines.push_back(std::string(layoutName(layout)) + " " + colorimetryName(c) + " (" + inputs +
                                            ")\n    ours   " + accuracy(mine, layout, c, legalOnly).describe() +
                                            "\n    libyuv " + accuracy(theirs, layout, c, legalOnly).describe());
                }
            }
        }
    }
    std::printf("\n# error against the exact formula (R, G, B bias = mean signed error)\n");
    for (const std::string& line : accuracyLines)
        std::printf("%s\n", line.c_str());
    return 0;
}
