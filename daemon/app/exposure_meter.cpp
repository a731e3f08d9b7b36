#include "exposure_meter.h"

#include <algorithm>
#include <cmath>

#include "core/error.h"

namespace lumar {

ExposureMeter::ExposureMeter(const ExposureMeterSettings& settings) : settings_(settings)
{
    if (settings_.gridColumns < 1 || settings_.gridRows < 1 || settings_.referenceFrames < 1 ||
        !(settings_.smoothing > 0.0 && settings_.smoothing <= 1.0) ||
        !(settings_.minRatio > 0.0 && settings_.minRatio <= 1.0 && settings_.maxRatio >= 1.0))
        throw InputError("exposure meter: needs a grid, reference frames, smoothing in (0, 1] and min <= 1 <= max");
    // Luma of sRGB-encoded values, decoded as sRGB: exact for grey, and for any colour a
    // uniform change of the light moves it by the same factor up to the curve's curvature.
    for (size_t code = 0; code < linear_.size(); ++code) {
        const double v = double(code) / 255.0;
        linear_[code] = v <= 0.04045 ? v / 12.92 : std::pow((v + 0.055) / 1.055, 2.4);
    }
}

void ExposureMeter::reset()
{
    reference_ = 0.0;
    referenceCount_ = 0;
    exposure_ = 1.0;
    frameExposure_ = 1.0;
}

double ExposureMeter::level(const Image8& luma) const
{
    if (luma.channels != 1 || luma.width < 1 || luma.height < 1)
        throw InputError("exposure meter: expected a non-empty 1-channel luma image");
    const int columns = std::min(settings_.gridColumns, luma.width);
    const int rows = std::min(settings_.gridRows, luma.height);
    std::array<int, 256> histogram{};
    for (int r = 0; r < rows; ++r) {
        const int y = int((long(r) * 2 + 1) * luma.height / (2L * rows)); // cell centres
        const uint8_t* row = luma.row(y);
        for (int c = 0; c < columns; ++c)
            ++histogram[row[(long(c) * 2 + 1) * luma.width / (2L * columns)]];
    }
    // The mean over ranks [n/4, 3n/4), a bin straddling either end counted in part.
    const double n = double(columns) * double(rows);
    const double low = 0.25 * n, high = 0.75 * n;
    double rank = 0.0, sum = 0.0;
    for (size_t code = 0; code < histogram.size(); ++code) {
        const double begin = rank, end = rank + histogram[code];
        rank = end;
        const double inside = std::min(end, high) - std::max(begin, low);
        if (inside > 0.0)
            sum += inside * linear_[code];
    }
    return sum / (high - low);
}

double ExposureMeter::update(const Image8& luma)
{
    const double current = level(luma);
    if (referenceCount_ < settings_.referenceFrames) {
        reference_ += (current - reference_) / double(++referenceCount_);
        return exposure_; // 1 until the reference is complete
    }
    // A black reference (lens cap, dark room at start-up) says nothing: keep the exposure.
    if (reference_ <= 1e-4)
        return exposure_;
    frameExposure_ = std::clamp(current / reference_, settings_.minRatio, settings_.maxRatio);
    exposure_ += settings_.smoothing * (frameExposure_ - exposure_);
    return exposure_;
}

} // namespace lumar
