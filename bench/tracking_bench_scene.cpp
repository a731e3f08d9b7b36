#include "bench/tracking_bench_scene.h"

#include <algorithm>
#include <cmath>
#include <map>

#include <apriltag/apriltag.h>
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

#include "core/error.h"
#include "tracking/apriltag_family.h"

namespace lumar {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kDeg = kPi / 180.0;

// Tags are rendered at 4x4 samples per pixel and box-filtered down, as real sensors integrate
// light over a pixel: their edges land where the ground truth says to a small fraction of a pixel.
constexpr int kSupersampling = 4;
constexpr int kTexelsPerCell = 16;
constexpr int kTagCells = 10; // tag36h11: the 8x8 black-bordered square plus a 1-cell white frame
constexpr double kInkBlack = 25.0, kPaperWhite = 230.0;
// The cluttered plane around the tags: 2.4 m square, ~1.2 mm per texel.
constexpr int kBackgroundTexels = 2048;
constexpr double kBackgroundMetres = 2.4;
constexpr double kFloorGrey = 110.0, kSkyGrey = 190.0;
constexpr int kMinSide = 64, kMaxSide = 8192;

double lerp(double a, double b, double s)
{
    return a + (b - a) * s;
}

uint64_t mix(uint64_t x)
{
    // SplitMix64's finaliser: decorrelates the seeds of neighbouring conditions and frames.
    x += 0x9e3779b97f4a7c15ULL;
    x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ULL;
    x = (x ^ (x >> 27)) * 0x94d049bb133111ebULL;
    return x ^ (x >> 31);
}

cv::Matx33d planeToImage(const CameraIntrinsics& k, const Pose& cameraFromWorld)
{
    const glm::dmat3& R = cameraFromWorld.R;
    const glm::dvec3& t = cameraFromWorld.t;
    const cv::Matx33d K(k.fx, 0, k.cx, 0, k.fy, k.cy, 0, 0, 1);
    // World plane point (X, Y, 0) -> camera: X r1 + Y r2 + t (glm is column-major).
    return K * cv::Matx33d(R[0][0], R[1][0], t.x, R[0][1], R[1][1], t.y, R[0][2], R[1][2], t.z);
}

// Clutter: grey patches, discs and tag-like squares with random bits (distractors that must
// not decode), so that false positives have something to come from.
cv::Mat makeBackground(uint64_t seed)
{
    cv::Mat texture(kBackgroundTexels, kBackgroundTexels, CV_8UC1, cv::Scalar(150));
    cv::RNG rng(mix(seed ^ 0x6261636bULL));
    const double texelsPerMetre = kBackgroundTexels / kBackgroundMetres;
    for (int i = 0; i < 400; ++i) {
        const cv::Point c(rng.uniform(0, kBackgroundTexels), rng.uniform(0, kBackgroundTexels));
        const int w = int(rng.uniform(0.01, 0.12) * texelsPerMetre), h = int(rng.uniform(0.01, 0.12) * texelsPerMetre);
        const cv::Scalar grey(rng.uniform(30, 230));
        if (i % 3 == 0)
            cv::circle(texture, c, w / 2, grey, cv::FILLED, cv::LINE_AA);
        else
            cv::rectangle(texture, cv::Rect(c.x - w / 2, c.y - h / 2, w, h), grey, cv::FILLED);
    }
    for (int i = 0; i < 40; ++i) {
        const int cell = int(rng.uniform(0.008, 0.02) * texelsPerMetre);
        const cv::Point origin(rng.uniform(0, kBackgroundTexels - 10 * cell),
                               rng.uniform(0, kBackgroundTexels - 10 * cell));
        cv::rectangle(texture, cv::Rect(origin, cv::Size(10 * cell, 10 * cell)), cv::Scalar(kPaperWhite), cv::FILLED);
        cv::rectangle(texture, cv::Rect(origin + cv::Point(cell, cell), cv::Size(8 * cell, 8 * cell)),
                      cv::Scalar(kInkBlack), cv::FILLED);
        for (int b = 0; b < 36; ++b)
            if (rng.uniform(0, 2) == 1)
                cv::rectangle(
                    texture, cv::Rect(origin + cv::Point((2 + b % 6) * cell, (2 + b / 6) * cell), cv::Size(cell, cell)),
                    cv::Scalar(kPaperWhite), cv::FILLED);
    }
    return texture;
}

// Texel (u, v) of the background (centred on the world origin, row 0 along +y) -> plane (X, Y).
cv::Matx33d planeFromBackgroundTexel()
{
    const double m = kBackgroundMetres / kBackgroundTexels;
    const double half = 0.5 * (kBackgroundTexels - 1) * m;
    return {m, 0, -half, 0, -m, half, 0, 0, 1};
}

// Texel (u, v) of a tag's texture -> plane (X, Y): column 0 along the tag's -x edge, row 0
// along its +y edge, texel centres at integer coordinates (OpenCV's warp convention).
cv::Matx33d planeFromTagTexel(const BenchTag& tag)
{
    const double cell = tag.size / 8.0;
    const double a = cell / kTexelsPerCell;
    const double b = cell * (0.5 / kTexelsPerCell - kTagCells / 2.0);
    return {a, 0, b + tag.position.x, 0, -a, -b + tag.position.y, 0, 0, 1};
}

std::vector<BenchCondition> makeConditions()
{
    const std::vector<BenchTag> one{{0, 0.16, {0.0, 0.0}}};
    std::vector<BenchCondition> c;
    c.push_back({.name = "clean", .tags = one});
    c.push_back({.name = "noise", .tags = one, .noiseSigma = 10.0});
    c.push_back({.name = "motion_blur", .tags = one, .motionBlurPx = 14.0});
    c.push_back({.name = "defocus", .tags = one, .defocusSigmaPx = 2.5});
    c.push_back({.name = "low_light", .tags = one, .lowLight = true});
    c.push_back({.name = "steep_75deg",
                 .tags = one,
                 .minTiltDeg = 55.0,
                 .maxTiltDeg = 75.0,
                 .minDistance = 0.4,
                 .maxDistance = 1.0});
    c.push_back({.name = "occlusion", .tags = {{0, 0.16, {-0.12, 0.0}}, {7, 0.16, {0.12, 0.0}}}, .occlude = true});
    c.push_back({.name = "several_tags",
                 .tags = {{1, 0.12, {-0.2, 0.1}},
                          {2, 0.08, {0.0, 0.15}},
                          {3, 0.16, {0.2, 0.05}},
                          {4, 0.10, {-0.15, -0.15}},
                          {5, 0.12, {0.15, -0.15}}},
                 .minDistance = 0.8,
                 .maxDistance = 1.6});
    c.push_back({.name = "no_tags",
                 .tags = {{0, 0.16, {-0.95, -0.95}}},
                 .maxTiltDeg = 30.0,
                 .minDistance = 0.4,
                 .maxDistance = 0.8,
                 .lookAway = true});
    return c;
}

} // namespace

struct TrackingBenchScene::Impl {
    CameraIntrinsics k;
    uint64_t seed = 0;
    cv::Mat background;
    mutable std::map<int, cv::Mat> tagTextures; // by id, made when first drawn

    // The tag's printed image from the family's own tables, drawn as apriltag_to_image()
    // draws it (that function's result cannot be freed: Debian's library does not export
    // image_u8_destroy): a white ring, the black border, the data bits, row 0 the +y edge.
    static cv::Mat tagTexture(int id)
    {
        static const AprilTagFamilyPtr family = createAprilTagFamily("tag36h11");
        const apriltag_family_t& f = *family;
        const int total = f.total_width, border = f.width_at_border;
        cv::Mat cells(total, total, CV_8UC1, cv::Scalar(kInkBlack));
        const int whiteStart = (total - border - 2) / 2;
        cv::rectangle(cells, cv::Rect(whiteStart, whiteStart, border + 2, border + 2), cv::Scalar(kPaperWhite), 1);
        const int borderStart = (total - border) / 2;
        const uint64_t code = f.codes[id];
        for (uint32_t i = 0; i < f.nbits; ++i)
            if (code & (uint64_t(1) << (f.nbits - i - 1)))
                cells.at<uint8_t>(int(f.bit_y[i]) + borderStart, int(f.bit_x[i]) + borderStart) = uint8_t(kPaperWhite);
        cv::Mat texture;
        cv::resize(cells, texture, {}, kTexelsPerCell, kTexelsPerCell, cv::INTER_NEAREST);
        return texture;
    }

    Pose cameraFromWorld(const BenchCondition& c, size_t condition, int frame, int frames) const
    {
        cv::RNG rng(mix(seed * 1000003ULL + condition));
        double phase[6];
        for (double& p : phase)
            p = rng.uniform(0.0, 2.0 * kPi);
        const double s = 2.0 * kPi * (frame + 0.5) / std::max(1, frames);
        const double tilt = lerp(c.minTiltDeg, c.maxTiltDeg, 0.5 - 0.5 * std::cos(s + phase[0])) * kDeg;
        const double distance = lerp(c.minDistance, c.maxDistance, 0.5 - 0.5 * std::cos(s + phase[1]));
        const double azimuth = (-90.0 + 35.0 * std::sin(s + phase[2])) * kDeg;
        const double roll = 12.0 * kDeg * std::sin(2.0 * s + phase[3]);
        glm::dvec2 centre(0.0);
        for (const BenchTag& tag : c.tags)
            centre += tag.position;
        centre /= double(c.tags.size());
        if (c.lookAway)
            centre = {0.35, 0.3};
        const glm::dvec3 aim(centre + 0.03 * glm::dvec2(std::sin(3.0 * s + phase[4]), std::cos(2.0 * s + phase[5])),
                             0.0);
        const glm::dvec3 eye = aim + distance * glm::dvec3(std::sin(tilt) * std::cos(azimuth),
                                                           std::sin(tilt) * std::sin(azimuth), std::cos(tilt));
        // OpenCV camera axes: z forward, y down (world -y seen upright), x = y cross z.
        const glm::dvec3 forward = glm::normalize(aim - eye);
        const glm::dvec3 minusY(0.0, -1.0, 0.0);
        const glm::dvec3 levelDown = glm::normalize(minusY - glm::dot(minusY, forward) * forward);
        const glm::dvec3 levelRight = glm::cross(levelDown, forward);
        const glm::dvec3 right = std::cos(roll) * levelRight + std::sin(roll) * levelDown;
        const glm::dvec3 down = glm::cross(forward, right);
        Pose pose;
        for (int i = 0; i < 3; ++i) {
            pose.R[i][0] = right[i];
            pose.R[i][1] = down[i];
            pose.R[i][2] = forward[i];
        }
        pose.t = -(pose.R * eye);
        return pose;
    }

    // Renders the tags (with the background around them) at kSupersampling and pastes the
    // box-filtered result over `image`, one bounding rectangle at a time.
    const cv::Mat& textureOf(int id) const
    {
        auto it = tagTextures.find(id);
        if (it == tagTextures.end())
            it = tagTextures.emplace(id, tagTexture(id)).first;
        return it->second;
    }

    void renderTags(const BenchCondition& c, const cv::Matx33d& plane, const Pose& cameraFromWorld,
                    cv::Mat& image) const
    {
        for (const BenchTag& tag : c.tags) {
            const double half = 0.5 * tag.size * kTagCells / 8.0;
            double minX = 1e9, minY = 1e9, maxX = -1e9, maxY = -1e9;
            bool inFront = true;
            for (const glm::dvec2 corner :
                 {glm::dvec2(-half, -half), glm::dvec2(half, -half), glm::dvec2(half, half), glm::dvec2(-half, half)}) {
                const glm::dvec3 p = cameraFromWorld.apply(glm::dvec3(tag.position + corner, 0.0));
                inFront = inFront && p.z > 0.05;
                const glm::dvec2 q = k.project(p);
                minX = std::min(minX, q.x);
                minY = std::min(minY, q.y);
                maxX = std::max(maxX, q.x);
                maxY = std::max(maxY, q.y);
            }
            if (!inFront)
                continue;
            const int x0 = std::max(0, int(std::floor(minX)) - 2), y0 = std::max(0, int(std::floor(minY)) - 2);
            const int x1 = std::min(k.width, int(std::ceil(maxX)) + 3),
                      y1 = std::min(k.height, int(std::ceil(maxY)) + 3);
            if (x1 <= x0 || y1 <= y0)
                continue;
            constexpr double S = kSupersampling;
            const cv::Matx33d toHighRes(S, 0, -S * x0 + (S - 1) / 2, 0, S, -S * y0 + (S - 1) / 2, 0, 0, 1);
            const cv::Size size((x1 - x0) * kSupersampling, (y1 - y0) * kSupersampling);
            cv::Mat highRes;
            cv::warpPerspective(background, highRes, cv::Mat(toHighRes * plane * planeFromBackgroundTexel()), size,
                                cv::INTER_LINEAR, cv::BORDER_CONSTANT, cv::Scalar(kFloorGrey));
            // Every tag, not just this one: a neighbour may reach into this rectangle.
            for (size_t i = 0; i < c.tags.size(); ++i)
                cv::warpPerspective(textureOf(c.tags[i].id), highRes,
                                    cv::Mat(toHighRes * plane * planeFromTagTexel(c.tags[i])), size, cv::INTER_LINEAR,
                                    cv::BORDER_TRANSPARENT);
            cv::Mat patch;
            cv::resize(highRes, patch, cv::Size(x1 - x0, y1 - y0), 0, 0, cv::INTER_AREA);
            patch.copyTo(image(cv::Rect(x0, y0, x1 - x0, y1 - y0)));
        }
    }

    // Pixels whose ray does not hit the plane in front of the camera see a flat sky.
    void paintSky(const Pose& cameraFromWorld, cv::Mat& image) const
    {
        const glm::dvec3 up = cameraFromWorld.R * glm::dvec3(0.0, 0.0, 1.0);
        for (int y = 0; y < image.rows; ++y) {
            uint8_t* row = image.ptr<uint8_t>(y);
            const double base = up.y * (y - k.cy) / k.fy + up.z;
            for (int x = 0; x < image.cols; ++x)
                if (up.x * (x - k.cx) / k.fx + base >= 0.0)
                    row[x] = uint8_t(kSkyGrey);
        }
    }

    // A flat grey patch over the whole tag and its white ring (a hand, a shadow).
    void cover(const BenchTag& tag, const Pose& cameraFromWorld, cv::Mat& image) const
    {
        const double outer = 0.5 * tag.size * kTagCells / 8.0 + 0.01;
        std::vector<cv::Point> polygon;
        for (const glm::dvec2 corner : {glm::dvec2(-outer, -outer), glm::dvec2(outer, -outer), glm::dvec2(outer, outer),
                                        glm::dvec2(-outer, outer)}) {
            const glm::dvec3 p = cameraFromWorld.apply(glm::dvec3(tag.position + corner, 0.0));
            if (p.z <= 0.05)
                return;
            const glm::dvec2 px = k.project(p);
            polygon.emplace_back(int(std::lround(px.x * 16.0)), int(std::lround(px.y * 16.0)));
        }
        cv::fillConvexPoly(image, polygon, cv::Scalar(120), cv::LINE_AA, 4);
    }

    // A flat grey patch over part of the first tag, reaching in from one edge past its border.
    void occlude(const BenchTag& tag, const Pose& cameraFromWorld, cv::RNG& rng, cv::Mat& image) const
    {
        const double s = tag.size;
        const double depth = rng.uniform(0.2, 0.35) * s, span = rng.uniform(0.35, 0.6) * s;
        const double along = rng.uniform(-0.5 * s + 0.5 * span, 0.5 * s - 0.5 * span);
        const double outer = 0.5 * s * kTagCells / 8.0 + 0.01;
        // The patch in the marker frame, reaching in from the -y edge, then turned to a random edge.
        const glm::dvec2 local[4] = {{along - 0.5 * span, -outer},
                                     {along + 0.5 * span, -outer},
                                     {along + 0.5 * span, -0.5 * s + depth},
                                     {along - 0.5 * span, -0.5 * s + depth}};
        const double turn = 0.5 * kPi * rng.uniform(0, 4);
        std::vector<cv::Point> polygon;
        for (const glm::dvec2& p : local) {
            const glm::dvec2 q(std::cos(turn) * p.x - std::sin(turn) * p.y,
                               std::sin(turn) * p.x + std::cos(turn) * p.y);
            const glm::dvec2 px = k.project(cameraFromWorld.apply(glm::dvec3(tag.position + q, 0.0)));
            // fillConvexPoly's fixed point: 4 fractional bits.
            polygon.emplace_back(int(std::lround(px.x * 16.0)), int(std::lround(px.y * 16.0)));
        }
        cv::fillConvexPoly(image, polygon, cv::Scalar(rng.uniform(90, 170)), cv::LINE_AA, 4);
    }
};

TrackingBenchScene::TrackingBenchScene(int width, int height, uint64_t seed) : impl_(std::make_unique<Impl>())
{
    if (width < kMinSide || height < kMinSide || width > kMaxSide || height > kMaxSide)
        throw InputError("tracking bench: the image size must be between 64x64 and 8192x8192, got " +
                         std::to_string(width) + "x" + std::to_string(height));
    impl_->k = defaultIntrinsics(width, height);
    impl_->seed = seed;
    impl_->background = makeBackground(seed);
}

TrackingBenchScene::~TrackingBenchScene() = default;

const std::vector<BenchCondition>& TrackingBenchScene::conditions()
{
    static const std::vector<BenchCondition> list = makeConditions();
    return list;
}

const CameraIntrinsics& TrackingBenchScene::intrinsics() const
{
    return impl_->k;
}

void TrackingBenchScene::render(size_t condition, int frame, int frames, BenchFrame& out) const
{
    const BenchCondition& c = conditions().at(condition);
    const Pose cameraFromWorld = impl_->cameraFromWorld(c, condition, frame, frames);
    renderView(c, cameraFromWorld, mix(impl_->seed ^ mix(condition * 100003ULL + uint64_t(frame))), out);
}

void TrackingBenchScene::renderView(const BenchCondition& c, const Pose& cameraFromWorld, uint64_t noiseSeed,
                                    BenchFrame& out) const
{
    const Impl& s = *impl_;
    const cv::Matx33d plane = planeToImage(s.k, cameraFromWorld);

    cv::Mat image;
    cv::warpPerspective(s.background, image, cv::Mat(plane * planeFromBackgroundTexel()),
                        cv::Size(s.k.width, s.k.height), cv::INTER_LINEAR, cv::BORDER_CONSTANT, cv::Scalar(kFloorGrey));
    s.renderTags(c, plane, cameraFromWorld, image);
    s.paintSky(cameraFromWorld, image);

    cv::RNG rng(noiseSeed);
    if (c.occlude)
        s.occlude(c.tags.front(), cameraFromWorld, rng, image);
    for (const BenchTag& tag : c.tags)
        if (std::find(c.covered.begin(), c.covered.end(), tag.id) != c.covered.end())
            s.cover(tag, cameraFromWorld, image);

    cv::Mat light;
    image.convertTo(light, CV_32F);
    // Blur lengths are given for a 1280-pixel-wide image: the same optics at any resolution.
    const double pixelScale = s.k.width / 1280.0;
    if (c.motionBlurPx > 0.0) {
        // A centred linear kernel: the blurred edge is centred on the frame's pose.
        const bool fixed = c.motionBlurAngleDeg >= 0.0;
        const double length = std::max(1.0, c.motionBlurPx * pixelScale * (fixed ? 1.0 : rng.uniform(0.4, 1.0)));
        const double angle = fixed ? c.motionBlurAngleDeg * kDeg : rng.uniform(0.0, kPi);
        const int side = int(std::ceil(length)) | 1;
        cv::Mat kernel = cv::Mat::zeros(side, side, CV_32F);
        const double cx = 0.5 * (side - 1), dx = 0.5 * (length - 1) * std::cos(angle),
                     dy = 0.5 * (length - 1) * std::sin(angle);
        constexpr int kShift = 4;
        cv::line(kernel, cv::Point(int(std::lround((cx - dx) * 16)), int(std::lround((cx - dy) * 16))),
                 cv::Point(int(std::lround((cx + dx) * 16)), int(std::lround((cx + dy) * 16))), cv::Scalar(1.0), 1,
                 cv::LINE_AA, kShift);
        kernel /= cv::sum(kernel)[0];
        cv::filter2D(light, light, -1, kernel, cv::Point(-1, -1), 0.0, cv::BORDER_REPLICATE);
    }
    if (c.defocusSigmaPx > 0.0)
        cv::GaussianBlur(light, light, cv::Size(), c.defocusSigmaPx * pixelScale * rng.uniform(0.6, 1.0));
    double noise = c.noiseSigma;
    if (c.lowLight) {
        // A dark exposure (a fifth of the light) through a display gamma: white ends near 40.
        light *= 1.0 / 255.0;
        const double exposure = rng.uniform(0.15, 0.25); // drawn in any case: the same noise follows
        cv::pow(light * (c.exposure > 0.0 ? c.exposure : exposure), 1.2, light);
        light *= 255.0;
        noise = 4.0;
    }
    if (noise > 0.0) {
        cv::Mat n(light.size(), CV_32F);
        rng.fill(n, cv::RNG::NORMAL, 0.0, noise);
        light += n;
    }
    cv::Mat final8;
    light.convertTo(final8, CV_8U); // rounds and saturates

    out.luma.reshape(s.k.width, s.k.height, 1);
    for (int y = 0; y < s.k.height; ++y)
        std::copy_n(final8.ptr<uint8_t>(y), s.k.width, out.luma.row(y));

    out.tags.clear();
    const glm::dvec3 eyeInWorld = cameraFromWorld.inverse().t;
    for (const BenchTag& tag : c.tags) {
        BenchTagTruth truth;
        truth.id = tag.id;
        truth.size = tag.size;
        truth.cameraFromMarker = cameraFromWorld * Pose{glm::dmat3(1.0), glm::dvec3(tag.position, 0.0)};
        truth.visible = eyeInWorld.z > 0.0 && std::find(c.covered.begin(), c.covered.end(), tag.id) == c.covered.end();
        const auto corners = tagCornersInMarkerFrame(tag.size);
        for (size_t i = 0; i < 4; ++i) {
            const glm::dvec3 p = truth.cameraFromMarker.apply(corners[i]);
            truth.visible = truth.visible && p.z > 0.05;
            truth.corners[i] = s.k.project(p);
            truth.visible = truth.visible && truth.corners[i].x >= 1.0 && truth.corners[i].y >= 1.0 &&
                            truth.corners[i].x <= s.k.width - 2.0 && truth.corners[i].y <= s.k.height - 2.0;
        }
        out.tags.push_back(truth);
    }
}

} // namespace lumar
