#include "bench/tracking_scoring.h"

#include <algorithm>
#include <charconv>
#include <chrono>
#include <cmath>
#include <ctime>
#include <limits>
#include <utility>

#include <apriltag/apriltag.h>
#include <glm/gtc/quaternion.hpp>

#include "core/error.h"
#include "tracking/apriltag_family.h"

namespace lumar {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

} // namespace

glm::dvec2 centreOf(const std::array<glm::dvec2, 4>& corners)
{
    return 0.25 * (corners[0] + corners[1] + corners[2] + corners[3]);
}

FrameMatch matchDetections(const std::vector<BenchTagTruth>& truths, const std::vector<TagDetection>& found)
{
    FrameMatch match;
    match.detectionOf.assign(truths.size(), -1);
    for (size_t d = 0; d < found.size(); ++d) {
        const glm::dvec2 at = centreOf(found[d].corners);
        size_t best = truths.size();
        double bestDistance = kMatchRadiusPx;
        for (size_t t = 0; t < truths.size(); ++t) {
            if (truths[t].id != found[d].id || match.detectionOf[t] >= 0)
                continue;
            const double distance = glm::length(centreOf(truths[t].corners) - at);
            if (distance <= bestDistance) {
                bestDistance = distance;
                best = t;
            }
        }
        if (best == truths.size())
            ++match.falsePositives;
        else
            match.detectionOf[best] = int(d);
    }
    return match;
}

double rotationErrorDeg(const glm::dmat3& a, const glm::dmat3& b)
{
    const glm::dmat3 d = glm::transpose(a) * b;
    const double c = std::clamp((d[0][0] + d[1][1] + d[2][2] - 1.0) / 2.0, -1.0, 1.0);
    // acos loses precision near 0: the antisymmetric part's norm keeps small angles exact.
    const double s = 0.5 * glm::length(glm::dvec3(d[1][2] - d[2][1], d[2][0] - d[0][2], d[0][1] - d[1][0]));
    return std::atan2(s, c) * 180.0 / kPi;
}

glm::dvec3 rotationVector(const glm::dmat3& truth, const glm::dmat3& measured)
{
    glm::dquat q = glm::quat_cast(glm::transpose(truth) * measured);
    if (q.w < 0.0)
        q = -q;
    const glm::dvec3 v(q.x, q.y, q.z);
    const double s = glm::length(v);
    return s < 1e-15 ? glm::dvec3(0.0) : (2.0 * std::atan2(s, q.w) / s) * v;
}

double mean(const std::vector<double>& v)
{
    if (v.empty())
        return kNaN;
    double sum = 0.0;
    for (const double x : v)
        sum += x;
    return sum / double(v.size());
}

double median(std::vector<double> v)
{
    std::sort(v.begin(), v.end());
    const size_t n = v.size();
    return n == 0 ? kNaN : n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

double percentile95(std::vector<double> v)
{
    if (v.empty())
        return kNaN;
    std::sort(v.begin(), v.end());
    return v[std::min(v.size() - 1, size_t(0.95 * double(v.size() - 1) + 0.5))];
}

double standardDeviation(const std::vector<glm::dvec3>& samples)
{
    if (samples.size() < 2)
        return kNaN;
    glm::dvec3 sum(0.0);
    for (const glm::dvec3& s : samples)
        sum += s;
    const glm::dvec3 average = sum / double(samples.size());
    double squares = 0.0;
    for (const glm::dvec3& s : samples)
        squares += glm::dot(s - average, s - average);
    return std::sqrt(squares / double(samples.size() - 1));
}

std::string fixed(double v, int decimals)
{
    if (!std::isfinite(v))
        return "–";
    char text[64];
    const auto end = std::to_chars(text, text + sizeof(text), v, std::chars_format::fixed, decimals).ptr;
    return std::string(text, end);
}

MarkdownTable::MarkdownTable(std::vector<std::string> header, size_t textColumns)
    : header_(std::move(header)), textColumns_(textColumns)
{
}

void MarkdownTable::add(std::vector<std::string> cells)
{
    cells.resize(header_.size());
    rows_.push_back(std::move(cells));
}

std::string MarkdownTable::str() const
{
    const auto line = [](const std::vector<std::string>& cells) {
        std::string out = "|";
        for (const std::string& cell : cells)
            out += " " + cell + " |";
        return out + "\n";
    };
    std::string out = line(header_) + "|";
    for (size_t i = 0; i < header_.size(); ++i)
        out += i < textColumns_ ? "---|" : "---:|";
    out += "\n";
    for (const auto& row : rows_)
        out += line(row);
    return out;
}

double wallSeconds()
{
    return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

double processCpuSeconds()
{
    timespec t{};
    if (clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t) != 0)
        throw RuntimeError("clock_gettime(CLOCK_PROCESS_CPUTIME_ID) failed");
    return double(t.tv_sec) + 1e-9 * double(t.tv_nsec);
}

struct AprilTagDefaults::Impl {
    struct DetectorDeleter {
        void operator()(apriltag_detector_t* d) const { apriltag_detector_destroy(d); }
    };
    AprilTagFamilyPtr family; // outlives the detector, which borrows it
    std::unique_ptr<apriltag_detector_t, DetectorDeleter> detector;
};

AprilTagDefaults::AprilTagDefaults() : impl_(std::make_unique<Impl>())
{
    impl_->family = createAprilTagFamily("tag36h11");
    impl_->detector.reset(apriltag_detector_create());
    if (!impl_->detector)
        throw RuntimeError("cannot create the AprilTag detector");
    apriltag_detector_add_family(impl_->detector.get(), impl_->family.get()); // the default 2 correctable bits
}

AprilTagDefaults::~AprilTagDefaults() = default;

std::vector<TagDetection> AprilTagDefaults::detect(const Image8& luma, const TagSizes& sizes, const CameraIntrinsics& k)
{
    image_u8_t image{luma.width, luma.height, luma.width, const_cast<uint8_t*>(luma.data.data())};
    zarray_t* detections = apriltag_detector_detect(impl_->detector.get(), &image);
    if (!detections)
        throw RuntimeError("AprilTag detection failed");
    std::vector<TagDetection> result;
    for (int i = 0; i < zarray_size(detections); ++i) {
        apriltag_detection_t* det = nullptr;
        zarray_get(detections, i, &det);
        TagDetection d;
        d.id = det->id;
        d.hamming = det->hamming;
        d.decisionMargin = det->decision_margin;
        for (size_t c = 0; c < 4; ++c)
            d.corners[c] = {det->p[c][0] - 0.5, det->p[c][1] - 0.5}; // OpenCV's pixel convention
        const double size = sizes.of(d.id);
        d.hasPose = size > 0.0 && solveTagPose(d.corners, size, k, d.cameraFromMarker, d.reprojectionErrorPx);
        result.push_back(d);
    }
    apriltag_detections_destroy(detections);
    return result;
}

std::string AprilTagDefaults::settings() const
{
    const apriltag_detector_t& td = *impl_->detector;
    return "quad_decimate " + fixed(td.quad_decimate, 1) + ", quad_sigma " + fixed(td.quad_sigma, 1) +
           ", refine_edges " + std::to_string(int(td.refine_edges)) + ", decode_sharpening " +
           fixed(td.decode_sharpening, 2) + ", nthreads " + std::to_string(td.nthreads) + ", 2 correctable bits";
}

} // namespace lumar
