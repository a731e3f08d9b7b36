#include "capture/table_irradiance.h"

#include <algorithm>
#include <cmath>

#include "capture/convex_polygon.h"
#include "core/environment_frame.h"

namespace lumar {
namespace {

constexpr double kPi = 3.14159265358979323846;
// Below this elevation a direction's shadow outline would be needlessly long (over 100× the
// object's height); such directions carry almost no cos-weighted light.
constexpr float kMinSampleZ = 0.01f;
constexpr float kVisibleShadow = 0.002f;

float luminance(const float* rgb)
{
    return 0.2126f * rgb[0] + 0.7152f * rgb[1] + 0.0722f * rgb[2];
}

// Calls fill(i, j) for every grid cell whose centre lies inside the convex polygon `hull`.
template <typename Fill> void rasterise(const std::vector<glm::vec2>& hull, Fill&& fill)
{
    constexpr int n = TableIrradiance::kCells;
    constexpr float scale = TableIrradiance::kCellsPerMetre;
    if (hull.size() < 3) {
        return;
    }
    float minY = INFINITY;
    float maxY = -INFINITY;
    for (const glm::vec2& p : hull) {
        minY = std::min(minY, p.y);
        maxY = std::max(maxY, p.y);
    }
    // Cell j's centre is at y = −half + (j + 0.5) / scale.
    const auto toGrid = [](float metres) { return (metres + fake_scene::kTableHalfSize) * scale - 0.5f; };
    const int j0 = int(std::ceil(std::clamp(toGrid(minY), 0.0f, float(n))));
    const int j1 = int(std::floor(std::clamp(toGrid(maxY), -1.0f, float(n - 1))));
    for (int j = j0; j <= j1; ++j) {
        const float y = -fake_scene::kTableHalfSize + (float(j) + 0.5f) / scale;
        const glm::vec2 span = convexSpanAt(hull, y);
        if (!(span.x <= span.y)) {
            continue;
        }
        // Clamped before the conversions: a low direction's shadow reaches far off the table.
        const int i0 = int(std::ceil(std::clamp(toGrid(span.x), 0.0f, float(n))));
        const int i1 = int(std::floor(std::clamp(toGrid(span.y), -1.0f, float(n - 1))));
        for (int i = i0; i <= i1; ++i) {
            fill(i, j);
        }
    }
}

} // namespace

std::vector<LightSample> skyLightSamples(const ImageF& equirect, int count)
{
    // Rows of the upper hemisphere (environment +Y up is world +Z up): v < 0.5.
    const int width = equirect.width;
    const int rows = equirect.height / 2;
    const double pixelSolidAngle = (2.0 * kPi / width) * (kPi / equirect.height);
    std::vector<double> cdf(size_t(width) * size_t(rows));
    double total = 0.0;
    for (int y = 0; y < rows; ++y) {
        const double theta = (y + 0.5) * kPi / equirect.height;
        const double weight = std::cos(theta) * std::sin(theta) * pixelSolidAngle;
        for (int x = 0; x < width; ++x) {
            total += weight * std::max(0.0f, luminance(equirect.at(x, y)));
            cdf[size_t(y) * size_t(width) + size_t(x)] = total;
        }
    }
    std::vector<LightSample> samples;
    if (!(total > 0.0) || count <= 0) {
        return samples;
    }
    const glm::mat3 worldFromEnvironment(glm::transpose(environmentFromMarker()));
    samples.reserve(size_t(count));
    for (int k = 0; k < count; ++k) {
        // Stratified: the k-th of `count` equal slices of the cumulative weight. Where a slice
        // lands in its pixel's weight places the direction across the pixel; a golden-ratio
        // sequence places it down the pixel.
        const double target = (k + 0.5) / count * total;
        const size_t index = size_t(std::lower_bound(cdf.begin(), cdf.end(), target) - cdf.begin());
        const double before = index == 0 ? 0.0 : cdf[index - 1];
        const double across = (target - before) / std::max(cdf[index] - before, 1e-300);
        const double down = std::fmod((k + 1) * 0.6180339887498949, 1.0);
        const int x = int(index % size_t(width));
        const int y = int(index / size_t(width));
        const double u = (x + across) / width;
        const double v = (y + down) / equirect.height;
        const double theta = v * kPi;
        const double phi = (u - 0.5) * 2.0 * kPi;
        const glm::vec3 environment(float(std::sin(theta) * std::cos(phi)), float(std::cos(theta)),
                                    float(std::sin(theta) * std::sin(phi)));
        const float* rgb = equirect.at(x, y);
        // Each sample carries total/count of luminance-weighted irradiance, in its pixel's colour.
        const float share = float(total / count) / std::max(luminance(rgb), 1e-30f);
        samples.push_back({glm::normalize(worldFromEnvironment * environment),
                           share * glm::vec3(std::max(rgb[0], 0.0f), std::max(rgb[1], 0.0f), std::max(rgb[2], 0.0f))});
    }
    return samples;
}

TableIrradiance::TableIrradiance(const glm::vec3& unoccluded, const ImageF& equirect,
                                 const std::vector<FakeObject>& objects)
    : unoccluded_(unoccluded)
{
    if (objects.empty()) {
        return;
    }
    // 256 directions: the sky's darkening comes in steps of well under 1 % of E, and the
    // bake stays near 20 ms for a box (it is proportional to the shadows' area).
    const std::vector<LightSample> samples = skyLightSamples(equirect, 256);
    const size_t cellCount = size_t(kCells) * kCells;
    std::vector<glm::vec3> blocked(cellCount, glm::vec3(0.0f));
    std::vector<int> stamp(cellCount, -1); // the last sample that blocked a cell: counted once
    glm::vec3 sum(0.0f);
    std::vector<std::vector<glm::vec3>> outlines;
    for (const FakeObject& object : objects) {
        outlines.push_back(object.hullPoints());
    }
    bool any = false;
    for (size_t k = 0; k < samples.size(); ++k) {
        const LightSample& sample = samples[k];
        sum += sample.irradiance;
        if (sample.direction.z < kMinSampleZ) {
            continue;
        }
        const glm::vec2 slide = glm::vec2(sample.direction) / sample.direction.z;
        for (const std::vector<glm::vec3>& outline : outlines) {
            // The shadow along this direction: every point slid down it onto z = 0.
            std::vector<glm::vec2> projected;
            projected.reserve(outline.size());
            for (const glm::vec3& p : outline) {
                projected.push_back(glm::vec2(p) - p.z * slide);
            }
            rasterise(convexHull(std::move(projected)), [&](int i, int j) {
                const size_t c = size_t(j) * kCells + size_t(i);
                if (stamp[c] != int(k)) {
                    stamp[c] = int(k);
                    blocked[c] += sample.irradiance;
                    any = true;
                }
            });
        }
    }
    if (!any) {
        return;
    }
    cells_.resize(cellCount);
    std::vector<uint8_t> shadowed(cellCount, 0);
    bool visible = false;
    for (size_t c = 0; c < cellCount; ++c) {
        glm::vec3 remaining(1.0f);
        for (int ch = 0; ch < 3; ++ch) {
            if (sum[ch] > 0.0f) {
                remaining[ch] = std::clamp(1.0f - blocked[c][ch] / sum[ch], 0.0f, 1.0f);
            }
        }
        // Low sky directions cast faint shadows far across the table. Less than 0.2 % of the
        // light changes a code value by under 0.25 (sRGB's slope is at most 255 / 2.2 per
        // relative unit above its linear toe): such cells count as open, so the table's bake
        // and the tags take their fast path there.
        shadowed[c] = std::min({remaining.x, remaining.y, remaining.z}) < 1.0f - kVisibleShadow;
        cells_[c] = shadowed[c] ? unoccluded_ * remaining : unoccluded_;
        visible = visible || shadowed[c];
    }
    if (!visible) {
        cells_.clear();
        return;
    }
    quadShadowed_.assign(cellCount, 0);
    for (int j = 0; j < kCells; ++j) {
        for (int i = 0; i < kCells; ++i) {
            const int i1 = std::min(i + 1, kCells - 1);
            const int j1 = std::min(j + 1, kCells - 1);
            quadShadowed_[size_t(j * kCells + i)] =
                uint8_t(shadowed[size_t(j * kCells + i)] | shadowed[size_t(j * kCells + i1)] |
                        shadowed[size_t(j1 * kCells + i)] | shadowed[size_t(j1 * kCells + i1)]);
        }
    }
}

glm::vec3 TableIrradiance::at(float x, float y) const
{
    if (cells_.empty()) {
        return unoccluded_;
    }
    const Cell c = cell(x, y);
    const glm::vec3* row0 = cells_.data() + size_t(c.j) * kCells + size_t(c.i);
    const glm::vec3* row1 = row0 + kCells;
    const glm::vec3 bottom = row0[0] + c.fx * (row0[1] - row0[0]);
    const glm::vec3 top = row1[0] + c.fx * (row1[1] - row1[0]);
    return bottom + c.fy * (top - bottom);
}

} // namespace lumar
