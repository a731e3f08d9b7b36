// The real environment built from the camera (DESIGN.md §6.5) and exposure matching: camera
// frames of a known .hdr are synthesised on the CPU (per pixel: the ray through the
// intrinsics, turned by the camera's orientation, looked up in the map, clipped at the
// camera's white and sRGB-encoded), fed to the renderer with their orientations, and what it
// builds is compared with the map itself.
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <numbers>
#include <vector>

#include <glm/gtc/matrix_transform.hpp>
#include <gtest/gtest.h>

#include "exposure_meter.h"
#include "gl/gl_readback.h"
#include "gl/gl_test_support.h"
#include "gles_renderer/assets/builtin_shapes.h"
#include "gles_renderer/assets/environment_map.h"
#include "gles_renderer/ibl/cube_map.h"
#include "gles_renderer/ibl/sh_projection.h"

namespace lumar {
namespace {

constexpr double kPi = std::numbers::pi;

const ImageF& venice()
{
    static const ImageF map =
        loadHdrImage(std::filesystem::path(LUMAR_SOURCE_DIR) / "daemon/assets/env/venice_sunset_1k.hdr");
    return map;
}

// The camera's orientation in the environment frame (+Y up): looking along yaw (about +Y,
// from +X towards +Z) and pitch (up), upright. Columns: the OpenCV camera's x (right),
// y (down) and z (forward).
glm::dmat3 environmentFromCamera(double yawDeg, double pitchDeg)
{
    const double yaw = yawDeg * kPi / 180.0, pitch = pitchDeg * kPi / 180.0;
    const glm::dvec3 forward(std::cos(pitch) * std::cos(yaw), std::sin(pitch), std::cos(pitch) * std::sin(yaw));
    const glm::dvec3 right = glm::normalize(glm::cross(forward, glm::dvec3(0, 1, 0)));
    const glm::dvec3 down = glm::cross(forward, right);
    return glm::dmat3(right, down, forward);
}

// What a camera with orientation `r` records of `map` scaled by `scale`: linear values
// clipped at 1 (its white), sRGB-encoded to 8 bits.
Image8 synthesiseFrame(const ImageF& map, float scale, const CameraIntrinsics& k, const glm::dmat3& r)
{
    Image8 image(k.width, k.height, 3);
    for (int v = 0; v < k.height; ++v)
        for (int u = 0; u < k.width; ++u) {
            // Pixel u's centre is at u (camera_projection.cpp's convention).
            const glm::dvec3 ray((u - k.cx) / k.fx, (v - k.cy) / k.fy, 1.0);
            const glm::vec3 radiance = sampleEquirectBilinear(map, glm::vec3(glm::normalize(r * ray))) * scale;
            uint8_t* out = image.at(u, v);
            for (int c = 0; c < 3; ++c)
                out[c] = uint8_t(std::lround(255.0 * test::srgbEncode(std::min(double(radiance[c]), 1.0))));
        }
    return image;
}

SH9 readCoefficients(const IblMaps& maps)
{
    const ImageF texels = test::readTexture2D(maps.coefficients.name(), 1, 9);
    SH9 sh;
    for (size_t j = 0; j < 9; ++j)
        sh[j] = glm::vec3(texels.at(0, int(j))[0], texels.at(0, int(j))[1], texels.at(0, int(j))[2]);
    return sh;
}

// venice_sunset_1k.hdr times this has a mean radiance of about 0.25: a camera exposed for
// the sky and the water, the sun and its glare clipped.
constexpr float kSceneScale = 0.5f;

// An orbit: a full turn of yaw at each of four pitches, 90-degree horizontal field of view.
struct OrbitPose {
    double yawDeg, pitchDeg;
};
std::vector<OrbitPose> orbit()
{
    std::vector<OrbitPose> poses;
    for (const double pitch : {-55.0, -18.0, 18.0, 55.0})
        for (int step = 0; step < 12; ++step)
            poses.push_back({step * 30.0, pitch});
    return poses;
}

class CameraEnvironmentOrbit : public ::testing::TestWithParam<bool> {};

// After a full orbit the map has seen (nearly) the whole sphere, and its SH9 is the one of
// what the camera could record: the .hdr scaled and clipped at the camera's white.
TEST_P(CameraEnvironmentOrbit, BuildsTheMapTheCameraSees)
{
    const bool rgbm = GetParam();
    RenderOptions options;
    options.environmentMaps.ibl.forceRgbm = rgbm;
    const CameraIntrinsics k = test::makeIntrinsics(160, 120, 80, 80, 79.5, 59.5);
    LUMAR_RENDERER_OR_SKIP(renderer, k.width, k.height, options);
    renderer.setEnvironmentSource(EnvironmentSource::Camera);
    EXPECT_EQ(renderer.environmentCoverage(), 0.0);

    double coverage = 0.0;
    for (const OrbitPose& pose : orbit()) {
        const glm::dmat3 r = environmentFromCamera(pose.yawDeg, pose.pitchDeg);
        renderer.setEnvironmentRotation(r);
        renderer.render(synthesiseFrame(venice(), kSceneScale, k, r), k, {});
        const double now = renderer.environmentCoverage();
        EXPECT_GE(now, coverage) << "yaw " << pose.yawDeg << ", pitch " << pose.pitchDeg;
        EXPECT_GT(now, 0.0);
        if (coverage == 0.0) {
            EXPECT_LT(now, 0.2) << "one frame sees 0.14 of the sphere";
        }
        coverage = now;
    }
    // The frames' vertical field of view (74 degrees, less the edge ramp) reaches past both
    // poles from the outer pitches. Measured: 1.0.
    EXPECT_GT(coverage, 0.99);
    // The real environment's maps are rebuilt from the map every few frames: a few more
    // frames, and they show the last frames of the orbit too.
    for (int frame = 0; frame < 4; ++frame) {
        const glm::dmat3 r = environmentFromCamera(orbit().back().yawDeg, orbit().back().pitchDeg);
        renderer.setEnvironmentRotation(r);
        renderer.render(synthesiseFrame(venice(), kSceneScale, k, r), k, {});
    }

    const SH9 reference = projectSH9BruteForce(
        [](glm::vec3 d) { return glm::min(sampleEquirectBilinear(venice(), d) * kSceneScale, glm::vec3(1.0f)); }, 256);
    const double error = sh9RelativeError(readCoefficients(renderer.environmentMaps()), reference);
    // The error covers the quarter-size camera image, the 256 x 128 map, the 64-px mirror
    // cube and 8-bit frames. Measured: 0.0062 (float), 0.0057 (RGBM).
    EXPECT_LT(error, 0.02) << (rgbm ? "RGBM" : "float");
}

INSTANTIATE_TEST_SUITE_P(FloatAndRgbm, CameraEnvironmentOrbit, ::testing::Values(false, true),
                         [](const auto& instance) { return instance.param ? "Rgbm" : "Float"; });

// The camera source draws nothing over the frame: without virtual objects the output is the
// input, with shadows on, a light set and a phantom box (camera-textured in no map, since no
// object owns one; it writes depth and receives no shadow).
TEST(CameraEnvironment, PassesTheCameraImageThrough)
{
    const CameraIntrinsics k = test::makeIntrinsics(160, 120, 80, 80, 79.5, 59.5);
    RenderOptions options;
    options.shadows.enabled = true;
    LUMAR_RENDERER_OR_SKIP(renderer, k.width, k.height, options);
    renderer.setEnvironmentSource(EnvironmentSource::CameraOverHdr);
    renderer.setEnvironment(venice(), 1.0f);
    renderer.setLight(DirectionalLight{glm::dvec3(0.3, 1.0, 0.2), glm::vec3(1.0f), 2.0f});
    const ModelId box = renderer.addModel(makeCube());
    glm::dmat4 boxPose = glm::translate(glm::dmat4(1.0), glm::dvec3(0.1, 0.1, 1.0));
    boxPose = glm::scale(boxPose, glm::dvec3(0.3));
    const DrawItem phantom{box, boxPose, -1, true};
    for (int frame = 0; frame < 3; ++frame) {
        const glm::dmat3 r = environmentFromCamera(40.0 * frame, 10.0);
        const Image8 input = synthesiseFrame(venice(), kSceneScale, k, r);
        renderer.setEnvironmentRotation(r);
        renderer.render(input, k, {&phantom, 1});
        Image8 output;
        renderer.readback(output);
        ASSERT_EQ(output.data.size(), input.data.size());
        EXPECT_LE(test::maxCodeDifference(output, input), 1) << "frame " << frame;
    }
}

// A grey diffuse sphere 0.5 m in front of the camera, and the mean linear value of the
// pixels in its middle.
GltfModel diffuseSphere()
{
    GltfModel sphere = makeUvSphere(48, 24);
    GltfMaterial& m = sphere.materials[0];
    m.baseColorFactor = glm::vec4(0.4f, 0.4f, 0.4f, 1.0f);
    m.metallicFactor = 0.0f;
    m.roughnessFactor = 1.0f;
    return sphere;
}

double sphereMiddle(const Image8& frame)
{
    // The sphere (radius 0.1 m at 0.5 m, fx 80) spans 32 px round the centre: its middle 12 x 12.
    double sum = 0.0;
    int count = 0;
    for (int y = frame.height / 2 - 6; y < frame.height / 2 + 6; ++y)
        for (int x = frame.width / 2 - 6; x < frame.width / 2 + 6; ++x)
            for (int c = 0; c < 3; ++c, ++count)
                sum += test::srgbDecode(frame.at(x, y)[c] / 255.0);
    return sum / count;
}

Image8 lumaOf(const Image8& rgb)
{
    Image8 luma(rgb.width, rgb.height, 1);
    for (int y = 0; y < rgb.height; ++y)
        for (int x = 0; x < rgb.width; ++x) {
            const uint8_t* p = rgb.at(x, y);
            *luma.at(x, y) = uint8_t((299 * p[0] + 587 * p[1] + 114 * p[2] + 500) / 1000);
        }
    return luma;
}

class ExposureMatching : public ::testing::TestWithParam<EnvironmentSource> {};

// The camera image loses half its light (the lights dimmed, or the auto-exposure closed):
// within kFollowFrames frames the virtual sphere has lost half of its own, lit by the .hdr or
// by the environment built from the camera alike.
TEST_P(ExposureMatching, VirtualObjectsFollowTheCameraImage)
{
    const CameraIntrinsics k = test::makeIntrinsics(160, 120, 80, 80, 79.5, 59.5);
    LUMAR_RENDERER_OR_SKIP(renderer, k.width, k.height);
    const ModelId sphere = renderer.addModel(diffuseSphere());
    // The .hdr as the camera sees it at the reference exposure.
    renderer.setEnvironment(venice(), kSceneScale);
    renderer.setEnvironmentSource(GetParam());
    ExposureMeter meter;

    const glm::dmat3 r = environmentFromCamera(200.0, 5.0);
    const DrawItem item{sphere, glm::scale(test::translation(0, 0, 0.5), glm::dvec3(0.2)), 0};
    const auto run = [&](float scale, int frames) {
        const Image8 input = synthesiseFrame(venice(), scale, k, r);
        const Image8 luma = lumaOf(input);
        Image8 output;
        for (int frame = 0; frame < frames; ++frame) {
            renderer.setExposure(float(meter.update(luma)));
            renderer.setCameraImageExposure(float(meter.frameExposure()));
            renderer.setEnvironmentRotation(r);
            renderer.render(input, k, std::span(&item, 1));
        }
        renderer.readback(output);
        return sphereMiddle(output);
    };
    // First the camera turns round once at the reference exposure (the map sees everything,
    // the sphere's front lit by what was seen behind the camera), then stands still.
    for (const OrbitPose& pose : orbit()) {
        const glm::dmat3 turned = environmentFromCamera(pose.yawDeg, pose.pitchDeg);
        renderer.setEnvironmentRotation(turned);
        renderer.render(synthesiseFrame(venice(), kSceneScale, k, turned), k, {});
    }
    constexpr int kFollowFrames = 8;
    const double before = run(kSceneScale, 12);
    const double after = run(0.5f * kSceneScale, kFollowFrames);
    ASSERT_GT(before, 0.02);
    // Half, within 8-bit quantisation of the sphere's pixels and the meter's residual after
    // 8 frames of smoothing (0.5^8 of the step). Measured: 0.5016 (hdr), 0.5017 (camera,
    // camera+hdr).
    EXPECT_NEAR(after / before, 0.5, 0.02) << "before " << before << ", after " << after;
    EXPECT_NEAR(meter.exposure(), 0.5, 0.02);
}

INSTANTIATE_TEST_SUITE_P(Sources, ExposureMatching,
                         ::testing::Values(EnvironmentSource::Hdr, EnvironmentSource::Camera,
                                           EnvironmentSource::CameraOverHdr),
                         [](const auto& instance) {
                             return instance.param == EnvironmentSource::Hdr      ? "Hdr"
                                    : instance.param == EnvironmentSource::Camera ? "Camera"
                                                                                  : "CameraOverHdr";
                         });

} // namespace
} // namespace lumar
