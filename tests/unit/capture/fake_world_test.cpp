// The fake camera under an environment map: the map shows where no table is, the table and
// the objects on it are lit by it (exposure included), the objects hide what is behind them
// and shadow the table, and everything stays deterministic.
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "capture/fake_camera.h"
#include "config/config.h"
#include "core/environment_frame.h"
#include "core/error.h"
#include "gles_renderer/assets/environment_map.h"
#include "gles_renderer/ibl/cube_map.h"
#include "output/frame_writer.h"

namespace lumar {
namespace {

constexpr double kPi = 3.14159265358979323846;

std::filesystem::path hdrPath()
{
    return std::filesystem::path(LUMAR_SOURCE_DIR) / "daemon/assets/env/venice_sunset_1k.hdr";
}

const ImageF& hdr()
{
    static const ImageF map = loadHdrImage(hdrPath());
    return map;
}

// 640x360 without noise, under the shipped sunset.
CameraConfig worldConfig()
{
    CameraConfig config;
    config.width = 640;
    config.height = 360;
    config.noiseSigma = 0.0;
    config.fakeEnvironment = hdrPath();
    return config;
}

FakeObjectConfig box(glm::dvec3 size, glm::dvec2 offset, glm::dvec3 color)
{
    FakeObjectConfig object;
    object.shape = "box";
    object.tag = 0;
    object.size = size;
    object.offset = offset;
    object.color = color;
    return object;
}

double encode(double linear)
{
    const double v = std::clamp(linear, 0.0, 1.0);
    return 255.0 * (v <= 0.0031308 ? 12.92 * v : 1.055 * std::pow(v, 1.0 / 2.4) - 0.055);
}

double decode(double code)
{
    const double v = code / 255.0;
    return v <= 0.04045 ? v / 12.92 : std::pow((v + 0.055) / 1.055, 2.4);
}

// The world direction through the centre of pixel (x, y).
glm::dvec3 pixelRay(const FakeCamera& camera, uint64_t k, double x, double y)
{
    const CameraIntrinsics& K = camera.intrinsics();
    const glm::dvec3 inCamera((x - K.cx) / K.fx, (y - K.cy) / K.fy, 1.0);
    return glm::transpose(camera.cameraFromWorld(k).R) * inCamera;
}

glm::dvec3 eyeOf(const FakeCamera& camera, uint64_t k)
{
    return camera.cameraFromWorld(k).inverse().t;
}

glm::dvec2 project(const FakeCamera& camera, uint64_t k, const glm::dvec3& world)
{
    return camera.intrinsics().project(camera.cameraFromWorld(k).apply(world));
}

glm::dvec3 pixelAt(const Frame& frame, glm::dvec2 p)
{
    const int x = int(std::lround(p.x));
    const int y = int(std::lround(p.y));
    EXPECT_TRUE(x >= 0 && y >= 0 && x < frame.rgb.width && y < frame.rgb.height) << x << "," << y;
    const uint8_t* rgb = frame.rgb.at(std::clamp(x, 0, frame.rgb.width - 1), std::clamp(y, 0, frame.rgb.height - 1));
    return {rgb[0], rgb[1], rgb[2]};
}

// E(n)/π of the map for world normal n, as the renderer computes it (SH9).
glm::dvec3 whiteRadiance(const glm::dvec3& worldNormal)
{
    static const SH9 sh = projectEquirectSH9(hdr());
    return glm::dvec3(irradianceSH9(sh, glm::vec3(environmentFromMarker() * worldNormal))) / kPi;
}

// Whether the segment from `eye` along `d` (any length) to the table passes through the
// axis-aligned box [lo, hi].
bool rayHitsBox(const glm::dvec3& eye, const glm::dvec3& d, const glm::dvec3& lo, const glm::dvec3& hi)
{
    double t0 = 0.0;
    double t1 = -eye.z / d.z;
    for (int a = 0; a < 3; ++a) {
        const double ta = (lo[a] - eye[a]) / d[a];
        const double tb = (hi[a] - eye[a]) / d[a];
        t0 = std::max(t0, std::min(ta, tb));
        t1 = std::min(t1, std::max(ta, tb));
    }
    return t0 <= t1;
}

TEST(FakeWorld, TheEnvironmentShowsWhereNoTableIs)
{
    const FakeCamera camera(worldConfig());
    Frame frame;
    std::vector<double> errors;
    for (const uint64_t k : {60u, 100u, 140u}) {
        camera.render(k, frame);
        const glm::dvec3 eye = eyeOf(camera, k);
        for (int y = 0; y < frame.rgb.height; y += 2) {
            for (int x = 0; x < frame.rgb.width; x += 2) {
                const glm::dvec3 d = pixelRay(camera, k, x, y);
                // Well off the table (every ray of the pixel misses it): the map at infinity.
                const glm::dvec3 onPlane = eye - eye.z / d.z * d;
                if (d.z < 0.0 && std::max(std::abs(onPlane.x), std::abs(onPlane.y)) < 0.62) {
                    continue;
                }
                const glm::vec3 radiance =
                    sampleEquirectBilinear(hdr(), glm::vec3(environmentFromMarker() * glm::normalize(d)));
                const glm::dvec3 rendered = pixelAt(frame, {x, y});
                for (int c = 0; c < 3; ++c) {
                    errors.push_back(std::abs(rendered[c] - encode(radiance[c])));
                }
            }
        }
    }
    ASSERT_GT(errors.size(), 3000u) << "the trajectory should show the surroundings";
    std::sort(errors.begin(), errors.end());
    double mean = 0.0;
    for (const double e : errors) {
        mean += e / double(errors.size());
    }
    const double p99 = errors[errors.size() * 99 / 100];
    std::printf("environment vs the map: mean %.2f, 99th percentile %.1f, max %.1f code values (%zu samples)\n", mean,
                p99, errors.back(), errors.size());
    // The cube holds the map sampled at texel centres (0.2° apart at 640 px) and the pixel
    // averages four rays: on the map's smooth parts that is within rounding; its sharp edges
    // (pavement joints, the sun) make the tail.
    EXPECT_LT(mean, 1.5);
    EXPECT_LT(p99, 10.0);
}

// Halving the exposure halves the table's linear values, under the map and in the plain room.
void expectTableFollowsExposure(const CameraConfig& config)
{
    FakeCamera camera(config);
    Frame full;
    Frame half;
    const uint64_t k = 30;
    camera.render(k, full);
    camera.setExposure(0.5); // from the next frame on
    EXPECT_DOUBLE_EQ(camera.exposure(), 0.5);
    camera.render(k, half);
    double sumFull = 0.0;
    double sumHalf = 0.0;
    int pixels = 0;
    const glm::dvec3 eye = eyeOf(camera, k);
    for (int y = 0; y < full.rgb.height; y += 3) {
        for (int x = 0; x < full.rgb.width; x += 3) {
            const glm::dvec3 d = pixelRay(camera, k, x, y);
            const glm::dvec3 p = eye - eye.z / d.z * d;
            // Plain table, off the tag (0.2 m frame at the origin), codes clear of clipping.
            if (d.z >= 0.0 || std::max(std::abs(p.x), std::abs(p.y)) > 0.55 ||
                std::max(std::abs(p.x), std::abs(p.y)) < 0.12) {
                continue;
            }
            for (int c = 0; c < 3; ++c) {
                const double a = full.rgb.at(x, y)[c];
                if (a < 20.0 || a > 240.0) {
                    continue;
                }
                sumFull += decode(a);
                sumHalf += decode(half.rgb.at(x, y)[c]);
                ++pixels;
            }
        }
    }
    ASSERT_GT(pixels, 5000);
    // Each code is rounded (±0.5 code, under 1 % of a linear value above code 50): the sums
    // over thousands of samples agree within 1 %.
    EXPECT_NEAR(sumHalf / sumFull, 0.5, 0.005) << pixels << " samples";
    EXPECT_THROW(camera.setExposure(0.0), InputError);
    EXPECT_THROW(camera.setExposure(-1.0), InputError);
    EXPECT_THROW(camera.setExposure(std::nan("")), InputError);
}

TEST(FakeWorld, TheTableFollowsTheExposure)
{
    expectTableFollowsExposure(worldConfig());
    CameraConfig room = worldConfig();
    room.fakeEnvironment.clear();
    expectTableFollowsExposure(room);
}

TEST(FakeWorld, ABoxHidesTheTableAndShowsItsShadedColour)
{
    CameraConfig config = worldConfig();
    const glm::dvec3 albedo(0.2, 0.6, 0.1);
    config.fakeObjects = {box({0.08, 0.08, 0.1}, {0.0, 0.2}, albedo)};
    const FakeCamera withBox(config);
    const FakeCamera without(worldConfig());
    Frame a;
    Frame b;
    const uint64_t k = 0;
    withBox.render(k, a);
    without.render(k, b);
    // The top's centre and the face towards the camera (−y: the camera stays on the −y side).
    const glm::dvec2 top = project(withBox, k, {0.0, 0.2, 0.1});
    const glm::dvec2 front = project(withBox, k, {0.0, 0.16, 0.05});
    struct Face {
        glm::dvec2 pixel;
        glm::dvec3 normal;
    };
    for (const Face& face : {Face{top, {0, 0, 1}}, Face{front, {0, -1, 0}}}) {
        const glm::dvec3 expected = albedo * whiteRadiance(face.normal);
        const glm::dvec3 rendered = pixelAt(a, face.pixel);
        const glm::dvec3 tableThere = pixelAt(b, face.pixel);
        for (int c = 0; c < 3; ++c) {
            EXPECT_NEAR(rendered[c], encode(expected[c]), 1.0) << "channel " << c;
        }
        EXPECT_GT(glm::length(rendered - tableThere), 30.0) << "the box hides the table";
    }
    // Far from the box, on its sunny side, the table is as without it (the box takes a
    // fraction of a percent of the sky there: within a code value or two).
    const glm::dvec2 far = project(withBox, k, {0.3, -0.05, 0.0});
    EXPECT_LE(glm::length(pixelAt(a, far) - pixelAt(b, far)), 2.0);
}

TEST(FakeWorld, ATexturedBoxShowsItsTexture)
{
    const std::filesystem::path dir = std::filesystem::temp_directory_path() / "lumar-fake-world-texture";
    std::filesystem::create_directories(dir);
    Image8 texture(4, 4, 3);
    for (size_t i = 0; i < texture.data.size(); i += 3) {
        texture.data[i] = 200;
        texture.data[i + 1] = 60;
        texture.data[i + 2] = 120;
    }
    writePng(dir / "plain.png", texture);
    CameraConfig config = worldConfig();
    FakeObjectConfig object = box({0.08, 0.08, 0.1}, {0.0, 0.2}, glm::dvec3(0.0));
    object.texture = dir / "plain.png";
    config.fakeObjects = {object};
    const FakeCamera camera(config);
    Frame frame;
    camera.render(0, frame);
    const glm::dvec3 albedo(decode(200), decode(60), decode(120));
    const glm::dvec3 expected = albedo * whiteRadiance({0, 0, 1});
    const glm::dvec3 rendered = pixelAt(frame, project(camera, 0, {0.0, 0.2, 0.1}));
    for (int c = 0; c < 3; ++c) {
        EXPECT_NEAR(rendered[c], encode(expected[c]), 1.0) << "channel " << c;
    }
    std::filesystem::remove_all(dir);
}

TEST(FakeWorld, TheTableIsDarkerInABoxsShadow)
{
    // The sun: the map's brightest pixel, turned into the world frame.
    const ImageF& map = hdr();
    int best = 0;
    for (int i = 1; i < map.width * map.height; ++i) {
        const auto lum = [&](int p) { return map.data[3 * p] + map.data[3 * p + 1] + map.data[3 * p + 2]; };
        best = lum(i) > lum(best) ? i : best;
    }
    const double theta = (best / map.width + 0.5) / map.height * kPi;
    const double phi = ((best % map.width + 0.5) / map.width - 0.5) * 2.0 * kPi;
    const glm::dvec3 sunInMap(std::sin(theta) * std::cos(phi), std::cos(theta), std::sin(theta) * std::sin(phi));
    const glm::dvec3 sun = glm::transpose(environmentFromMarker()) * sunInMap;
    ASSERT_GT(sun.z, 0.0);
    const glm::dvec2 away = -glm::normalize(glm::dvec2(sun));

    CameraConfig config = worldConfig();
    const glm::dvec2 centre(-0.1, 0.25);
    config.fakeObjects = {box({0.08, 0.08, 0.12}, centre, {0.5, 0.5, 0.5})};
    const FakeCamera withBox(config);
    const FakeCamera without(worldConfig());
    // 3 cm from the box's footprint, away from the sun and towards it; and far away.
    const double reach = 0.04 * (std::abs(away.x) + std::abs(away.y)) + 0.03;
    const glm::dvec3 shadowed(centre + reach * away, 0.0);
    const glm::dvec3 sunny(centre - reach * away, 0.0);
    const glm::dvec3 far(0.3, 0.0, 0.0); // 0.47 m away on the sunny side
    Frame a;
    Frame b;
    int checked = 0;
    for (const uint64_t k : {0u, 60u, 120u, 180u, 240u, 300u}) {
        const glm::dvec3 eye = eyeOf(withBox, k);
        const glm::dvec3 lo(centre - 0.04, 0.0);
        const glm::dvec3 hi(centre + 0.04, 0.12);
        if (rayHitsBox(eye, shadowed - eye, lo, hi) || rayHitsBox(eye, sunny - eye, lo, hi)) {
            continue; // the box hides a point from this frame's camera
        }
        withBox.render(k, a);
        without.render(k, b);
        // The linear ratio of the lit table with and without the box, at a small patch.
        const auto ratio = [&](const glm::dvec3& point) {
            const glm::dvec2 p = project(withBox, k, point);
            double lit = 0.0;
            double open = 0.0;
            for (int dy = -1; dy <= 1; ++dy) {
                for (int dx = -1; dx <= 1; ++dx) {
                    const glm::dvec3 ca = pixelAt(a, p + glm::dvec2(dx, dy));
                    const glm::dvec3 cb = pixelAt(b, p + glm::dvec2(dx, dy));
                    for (int c = 0; c < 3; ++c) {
                        lit += decode(ca[c]);
                        open += decode(cb[c]);
                    }
                }
            }
            return lit / open;
        };
        const double inShadow = ratio(shadowed);
        const double sunSide = ratio(sunny);
        const double farAway = ratio(far);
        std::printf("frame %llu: with/without the box: %.3f in its shadow, %.3f on its sunny side, %.3f far away\n",
                    static_cast<unsigned long long>(k), inShadow, sunSide, farAway);
        // Next to the box it blocks a good part of the sky (measured 0.69 on the side away
        // from the sun, 0.88 on the sun's side); 0.47 m away, under 1 % of it (measured 0.99).
        EXPECT_LT(inShadow, 0.8) << "frame " << k;
        EXPECT_LT(inShadow, sunSide - 0.1) << "frame " << k;
        EXPECT_NEAR(farAway, 1.0, 0.015) << "frame " << k;
        ++checked;
    }
    EXPECT_GE(checked, 2);
}

TEST(FakeWorld, ACylindersSilhouetteIsItsDiameterProjected)
{
    CameraConfig config = worldConfig();
    config.width = 1280;
    config.height = 720;
    FakeObjectConfig cylinder = box({0.08, 0.08, 0.12}, {0.0, 0.22}, {0.05, 0.1, 0.8});
    cylinder.shape = "cylinder";
    config.fakeObjects = {cylinder};
    const FakeCamera camera(config);
    Frame frame;
    for (const uint64_t k : {0u, 90u, 270u}) {
        camera.render(k, frame);
        // The silhouette at mid-height: the two points where the view grazes the side.
        const glm::dvec3 eye = eyeOf(camera, k);
        const glm::dvec3 centre(0.0, 0.22, 0.06);
        const glm::dvec2 toEye = glm::dvec2(eye - centre);
        const double distance = glm::length(toEye);
        const glm::dvec2 u = toEye / distance;
        const glm::dvec2 v(-u.y, u.x);
        const double r = 0.04;
        const double cosA = r / distance;
        const double sinA = std::sqrt(1.0 - cosA * cosA);
        const glm::dvec2 left = project(camera, k, centre + glm::dvec3(r * (cosA * u + sinA * v), 0.0));
        const glm::dvec2 right = project(camera, k, centre + glm::dvec3(r * (cosA * u - sinA * v), 0.0));
        const double expected = glm::length(right - left);
        // Walk the line through both, 30 px beyond each, and find where the blue begins and ends
        // (sub-pixel: where blueness crosses half way between the wood's and the cylinder's).
        const glm::dvec2 dir = (right - left) / expected;
        const auto blueness = [&](double s) {
            const glm::dvec3 c = pixelAt(frame, left + s * dir);
            return c.z - 0.5 * (c.x + c.y);
        };
        const double inside = blueness(0.5 * expected);
        const double outside = 0.5 * (blueness(-30.0) + blueness(expected + 30.0));
        const double threshold = 0.5 * (inside + outside);
        ASSERT_GT(inside - outside, 60.0) << "frame " << k;
        double first = NAN;
        double last = NAN;
        for (double s = -30.0; s <= expected + 30.0; s += 0.25) {
            if (blueness(s) > threshold) {
                first = std::isnan(first) ? s : first;
                last = s;
            }
        }
        const double measured = last - first;
        std::printf("frame %llu: cylinder silhouette %.2f px, projected diameter %.2f px\n",
                    static_cast<unsigned long long>(k), measured, expected);
        // Pixels are sampled at their centres (rounded positions): within a pixel either way.
        EXPECT_NEAR(measured, expected, 1.5) << "frame " << k;
        EXPECT_NEAR(first, 0.0, 1.5) << "frame " << k;
    }
}

TEST(FakeWorld, IsDeterministic)
{
    CameraConfig config = worldConfig();
    config.noiseSigma = 2.0;
    config.seed = 11;
    FakeObjectConfig cylinder = box({0.06, 0.06, 0.1}, {0.15, 0.2}, {0.3, 0.3, 0.8});
    cylinder.shape = "cylinder";
    config.fakeObjects = {box({0.08, 0.05, 0.1}, {-0.1, 0.22}, {0.7, 0.2, 0.1}), cylinder};
    FakeCamera a(config);
    const FakeCamera b(config);
    Frame fa;
    Frame fb;
    for (const uint64_t k : {0u, 77u, 301u}) {
        a.render(k, fa);
        b.render(k, fb);
        EXPECT_EQ(fa.rgb.data, fb.rgb.data) << "frame " << k;
        EXPECT_EQ(fa.luma.data, fb.luma.data) << "frame " << k;
    }
    // An exposure change and back re-lights to the very same frame.
    a.setExposure(0.7);
    a.render(5, fa);
    a.setExposure(1.0);
    a.render(77, fa);
    b.render(77, fb);
    EXPECT_EQ(fa.rgb.data, fb.rgb.data);
}

TEST(FakeWorld, RejectsBadObjectsAndExposure)
{
    const auto expectError = [](const CameraConfig& config, const std::string& fragment) {
        try {
            FakeCamera camera(config);
            ADD_FAILURE() << "no error for " << fragment;
        } catch (const InputError& e) {
            EXPECT_NE(std::string(e.what()).find(fragment), std::string::npos) << e.what();
        }
    };
    const auto withObject = [](FakeObjectConfig object) {
        CameraConfig config;
        config.width = 64;
        config.height = 36;
        config.fakeObjects = {object};
        return config;
    };
    const FakeObjectConfig good = box({0.1, 0.1, 0.1}, {0.0, 0.2}, {0.5, 0.5, 0.5});
    FakeObjectConfig bad = good;
    bad.tag = 3;
    expectError(withObject(bad), "camera.fake_objects[0].tag: tag 3 is not in camera.fake_tags");
    bad = good;
    bad.size.y = 0.0;
    expectError(withObject(bad), "camera.fake_objects[0].size");
    bad = good;
    bad.size.z = std::nan("");
    expectError(withObject(bad), "camera.fake_objects[0].size");
    bad = good;
    bad.color.x = 1.5;
    expectError(withObject(bad), "camera.fake_objects[0].color");
    bad = good;
    bad.shape = "sphere";
    expectError(withObject(bad), "camera.fake_objects[0].shape: 'sphere'");
    bad = good;
    bad.shape = "cylinder";
    bad.size.y = 0.2;
    expectError(withObject(bad), "camera.fake_objects[0].size: a cylinder");
    bad = good;
    bad.texture = "/nonexistent/label.png";
    expectError(withObject(bad), "/nonexistent/label.png: cannot read");
    CameraConfig dark = withObject(good);
    dark.exposure = 0.0;
    expectError(dark, "camera.exposure");
    dark.exposure = INFINITY;
    expectError(dark, "camera.exposure");
    CameraConfig noMap = withObject(good);
    noMap.fakeEnvironment = "/nonexistent/sky.hdr";
    expectError(noMap, "/nonexistent/sky.hdr");
}

} // namespace
} // namespace lumar
