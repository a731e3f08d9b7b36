#include "capture/sensor_noise.h"

#include <cmath>

namespace lumar {
namespace {

// The standard normal quantile by bisection on erfc: exact to double precision and only
// run once per table entry.
double normalQuantile(double p)
{
    double lo = -10.0;
    double hi = 10.0;
    for (int i = 0; i < 100; ++i) {
        const double mid = 0.5 * (lo + hi);
        const double cdf = 0.5 * std::erfc(-mid / std::sqrt(2.0));
        (cdf < p ? lo : hi) = mid;
    }
    return 0.5 * (lo + hi);
}

} // namespace

SensorNoise::SensorNoise(double sigma) : sigma_(sigma)
{
    // Entry i is the quantile at the centre of the i-th of 4096 equal-probability bins, so a
    // uniform index draws from the normal distribution (cut at ±3.5 sigma).
    const size_t n = table_.size();
    for (size_t i = 0; i < n; ++i) {
        table_[i] = float(sigma * normalQuantile((double(i) + 0.5) / double(n)));
    }
}

} // namespace lumar
