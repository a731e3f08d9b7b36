// Configuration parsing: the defaults, the shipped example, a full file, and one test per
// class of error, each checking the exact "FILE:LINE: key:" prefix of the one-line message.
#include <filesystem>
#include <fstream>

#include <gtest/gtest.h>

#include "config/config.h"
#include "config_fixture.h"
#include "core/error.h"

namespace lumar {
namespace {

namespace fs = std::filesystem;

class ConfigTest : public test::ConfigFixture {
protected:
    void SetUp() override
    {
        test::ConfigFixture::SetUp();
        fs::create_directories(dir_ / "clips");
        std::ofstream(dir_ / "env.hdr") << "#?RADIANCE\n";
        std::ofstream(dir_ / "clip.y4m") << "YUV4MPEG2 W16 H16\n";
    }
};

const std::string kObject = "[[markers]]\nid = 0\nsize = 0.16\n[[objects]]\nmodel = \"box.glb\"\nmarker = 0\n";

TEST_F(ConfigTest, EmptyFileGivesTheStructDefaults)
{
    const Config c = parse("");
    EXPECT_EQ(c.camera.source, "fake");
    EXPECT_EQ(c.camera.width, 1280);
    EXPECT_EQ(c.camera.height, 720);
    EXPECT_EQ(c.tracking.family, "tag36h11");
    EXPECT_TRUE(c.objects.empty());
}

TEST_F(ConfigTest, BuiltInDefaultNamesShippedAssets)
{
    const Config c = defaultConfig();
    ASSERT_EQ(c.objects.size(), 1u);
    EXPECT_TRUE(fs::is_regular_file(c.objects[0].model)) << c.objects[0].model;
    EXPECT_TRUE(fs::is_regular_file(c.environment.hdr)) << c.environment.hdr;
    EXPECT_TRUE(fs::is_regular_file(c.camera.calibration)) << c.camera.calibration;
    EXPECT_EQ(c.objects[0].marker, 0);
    EXPECT_DOUBLE_EQ(c.markerSize(0), 0.16);
    EXPECT_DOUBLE_EQ(c.markerSize(5), 0.0);
    ASSERT_EQ(c.camera.fakeTags.size(), 1u);
    EXPECT_DOUBLE_EQ(c.camera.fakeTags[0].size, 0.16);
}

TEST_F(ConfigTest, ShippedExampleEqualsTheBuiltInDefault)
{
    const fs::path example = fs::path(LUMAR_SOURCE_DIR) / "daemon/assets/lumar.toml";
    const Config a = loadConfig(example);
    const Config b = defaultConfig();
    EXPECT_EQ(a.logLevel, b.logLevel);
    EXPECT_EQ(a.camera.source, b.camera.source);
    EXPECT_EQ(a.camera.width, b.camera.width);
    EXPECT_EQ(a.camera.height, b.camera.height);
    EXPECT_EQ(a.camera.fps, b.camera.fps);
    EXPECT_EQ(a.camera.loop, b.camera.loop);
    EXPECT_EQ(a.camera.seed, b.camera.seed);
    EXPECT_EQ(a.camera.noiseSigma, b.camera.noiseSigma);
    EXPECT_EQ(a.camera.format, b.camera.format);
    EXPECT_EQ(a.camera.zeroCopy, b.camera.zeroCopy);
    EXPECT_TRUE(a.camera.controls.empty());
    EXPECT_TRUE(b.camera.controls.empty());
    EXPECT_EQ(fs::weakly_canonical(a.camera.calibration), fs::weakly_canonical(b.camera.calibration));
    ASSERT_EQ(a.camera.fakeTags.size(), b.camera.fakeTags.size());
    EXPECT_EQ(a.camera.fakeTags[0].id, b.camera.fakeTags[0].id);
    EXPECT_EQ(a.camera.fakeTags[0].size, b.camera.fakeTags[0].size);
    EXPECT_EQ(a.camera.fakeTags[0].position, b.camera.fakeTags[0].position);
    EXPECT_EQ(a.tracking.family, b.tracking.family);
    EXPECT_EQ(a.tracking.quadDecimate, b.tracking.quadDecimate);
    EXPECT_EQ(a.tracking.quadSigma, b.tracking.quadSigma);
    EXPECT_EQ(a.tracking.refineEdges, b.tracking.refineEdges);
    EXPECT_EQ(a.tracking.decodeSharpening, b.tracking.decodeSharpening);
    EXPECT_EQ(a.tracking.threads, b.tracking.threads);
    ASSERT_EQ(a.markers.size(), b.markers.size());
    EXPECT_EQ(a.markers[0].id, b.markers[0].id);
    EXPECT_EQ(a.markers[0].size, b.markers[0].size);
    ASSERT_EQ(a.objects.size(), b.objects.size());
    EXPECT_EQ(a.objects[0].name, b.objects[0].name);
    EXPECT_EQ(fs::weakly_canonical(a.objects[0].model), fs::weakly_canonical(b.objects[0].model));
    EXPECT_EQ(a.objects[0].marker, b.objects[0].marker);
    EXPECT_EQ(a.objects[0].offset, b.objects[0].offset);
    EXPECT_EQ(a.objects[0].rotationDeg, b.objects[0].rotationDeg);
    EXPECT_EQ(a.objects[0].scale, b.objects[0].scale);
    EXPECT_EQ(a.objects[0].size, b.objects[0].size);
    EXPECT_EQ(fs::weakly_canonical(a.environment.hdr), fs::weakly_canonical(b.environment.hdr));
    EXPECT_EQ(a.environment.intensity, b.environment.intensity);
    EXPECT_EQ(a.output.sink, b.output.sink);
    EXPECT_EQ(a.output.drmDevice, b.output.drmDevice);
    EXPECT_EQ(a.output.connector, b.output.connector);
    EXPECT_EQ(a.output.plane, b.output.plane);
    EXPECT_EQ(a.output.mode, b.output.mode);
    EXPECT_EQ(a.output.kmsApi, b.output.kmsApi);
    EXPECT_EQ(a.output.path, b.output.path);
}

TEST_F(ConfigTest, KmsSinkKeys)
{
    const Config c = parse("[output]\nsink = \"kms\"\ndrm_device = \"/dev/dri/card1\"\nconnector = \"HDMI-A-1\"\n"
                           "plane = \"overlay\"\nmode = \"1920x1080\"\n");
    EXPECT_EQ(c.output.sink, "kms");
    EXPECT_EQ(c.output.drmDevice, "/dev/dri/card1");
    EXPECT_EQ(c.output.connector, "HDMI-A-1");
    EXPECT_EQ(c.output.plane, "overlay");
    EXPECT_EQ(c.output.mode, "1920x1080");
    const Config d = parse("[output]\nsink = \"kms\"\n");
    EXPECT_EQ(d.output.drmDevice, "auto");
    EXPECT_EQ(d.output.connector, "");
    EXPECT_EQ(d.output.plane, "auto");
    EXPECT_EQ(d.output.mode, "auto");
    expectError("[output]\nmode = \"1920\"\n", "test.toml:2: output.mode: expected \"auto\" or WIDTHxHEIGHT");
    expectError("[output]\nmode = \"1920x1080p\"\n", "test.toml:2: output.mode:");
    expectError("[output]\nmode = \"0x1080\"\n", "test.toml:2: output.mode:");
    expectError("[output]\nplane = \"cursor\"\n", "test.toml:2: output.plane:");
    expectError("[output]\nkms_api = \"fbdev\"\n", "test.toml:2: output.kms_api:");
    expectError("[output]\ndrm_device = \"card0\"\n", "test.toml:2: output.drm_device:");
}

TEST_F(ConfigTest, FullFileReadsEveryField)
{
    const Config c = parse(R"(log_level = "capture:debug,*:warn"
[camera]
source = "y4m"
path = "clip.y4m"
width = 640
height = 480
fps = 25
loop = false
seed = 42
noise = 0.5
[[camera.fake_tags]]
id = 3
size = 0.1
position = [0.1, -0.2]
[[camera.fake_tags]]
id = 586
size = 0.05
position = [-0.3, 0.3]
[tracking]
family = "tag25h9"
quad_decimate = 1
quad_sigma = 0.8
refine_edges = false
decode_sharpening = 0.5
threads = 4
[[markers]]
id = 3
size = 0.1
[[objects]]
name = "a"
model = "box.glb"
marker = 3
offset = [0.01, 0.02, 0.03]
rotation = [10, 20, 30.5]
scale = 2.5
[environment]
hdr = "env.hdr"
intensity = 2
[output]
sink = "none"
path = "frames/../out.y4m"
)");
    EXPECT_EQ(c.logLevel, "capture:debug,*:warn");
    EXPECT_EQ(c.camera.source, "y4m");
    EXPECT_EQ(c.camera.path, dir_ / "clip.y4m");
    EXPECT_EQ(c.camera.width, 640);
    EXPECT_EQ(c.camera.height, 480);
    EXPECT_DOUBLE_EQ(c.camera.fps, 25.0);
    EXPECT_FALSE(c.camera.loop);
    EXPECT_EQ(c.camera.seed, 42u);
    EXPECT_DOUBLE_EQ(c.camera.noiseSigma, 0.5);
    ASSERT_EQ(c.camera.fakeTags.size(), 2u);
    EXPECT_EQ(c.camera.fakeTags[1].id, 586);
    EXPECT_EQ(c.camera.fakeTags[0].position, glm::dvec2(0.1, -0.2));
    EXPECT_EQ(c.tracking.family, "tag25h9");
    EXPECT_DOUBLE_EQ(c.tracking.quadDecimate, 1.0);
    EXPECT_DOUBLE_EQ(c.tracking.quadSigma, 0.8);
    EXPECT_FALSE(c.tracking.refineEdges);
    EXPECT_DOUBLE_EQ(c.tracking.decodeSharpening, 0.5);
    EXPECT_EQ(c.tracking.threads, 4);
    ASSERT_EQ(c.objects.size(), 1u);
    EXPECT_EQ(c.objects[0].name, "a");
    EXPECT_EQ(c.objects[0].model, dir_ / "box.glb");
    EXPECT_EQ(c.objects[0].offset, glm::dvec3(0.01, 0.02, 0.03));
    EXPECT_EQ(c.objects[0].rotationDeg, glm::dvec3(10, 20, 30.5));
    EXPECT_DOUBLE_EQ(c.objects[0].scale, 2.5);
    EXPECT_EQ(c.environment.hdr, dir_ / "env.hdr");
    EXPECT_DOUBLE_EQ(c.environment.intensity, 2.0);
    EXPECT_EQ(c.output.sink, "none");
    EXPECT_EQ(c.output.path, dir_ / "out.y4m");
}

TEST_F(ConfigTest, SyntaxErrorNamesTheLine)
{
    expectError("[camera]\nwidth = 640\nheight = = 3\n", "test.toml:3: ");
}

TEST_F(ConfigTest, UnknownKeys)
{
    expectError("colour = 1\n", "test.toml:1: colour: unknown key");
    expectError("[camera]\nwidth = 640\nwidht = 640\n", "test.toml:3: camera.widht: unknown key");
    expectError(kObject + "colour = \"red\"\n", "test.toml:7: objects[0].colour: unknown key");
    expectError("[cameras]\nwidth = 1\n", "test.toml:1: cameras: unknown key");
}

TEST_F(ConfigTest, WrongTypes)
{
    expectError("[camera]\nheight = \"tall\"\n", "test.toml:2: camera.height: expected an integer, found a string");
    expectError("[camera]\nwidth = 640.0\n", "test.toml:2: camera.width: expected an integer, found a number");
    expectError("[tracking]\nrefine_edges = 1\n", "test.toml:2: tracking.refine_edges: expected true or false");
    expectError("[environment]\nintensity = \"bright\"\n", "test.toml:2: environment.intensity: expected a number");
    expectError("camera = 3\n", "test.toml:1: camera: expected a table");
    expectError("markers = 3\n", "test.toml:1: markers: expected an array of tables");
    expectError(kObject + "offset = [1, 2]\n", "test.toml:7: objects[0].offset: expected an array of 3 numbers");
}

TEST_F(ConfigTest, IntegerAcceptedWhereANumberIsExpected)
{
    EXPECT_DOUBLE_EQ(parse("[camera]\nfps = 60\n").camera.fps, 60.0);
}

TEST_F(ConfigTest, OutOfRange)
{
    expectError("[camera]\nwidth = 8\n", "test.toml:2: camera.width: 8 is outside [16, 8192]");
    expectError("[camera]\nwidth = 641\n", "test.toml:2: camera.width: 641 must be even");
    expectError("[camera]\nfps = 0\n", "test.toml:2: camera.fps: 0 is outside (0, 240]");
    expectError("[camera]\nnoise = -1\n", "test.toml:2: camera.noise:");
    expectError("[camera]\nseed = -1\n", "test.toml:2: camera.seed: must not be negative");
    expectError("[tracking]\nquad_decimate = 0.5\n", "test.toml:2: tracking.quad_decimate:");
    expectError("[tracking]\nthreads = 0\n", "test.toml:2: tracking.threads:");
    expectError("[[markers]]\nid = 0\nsize = 0\n", "test.toml:3: markers[0].size:");
    expectError("[[camera.fake_tags]]\nid = 587\n", "test.toml:2: camera.fake_tags[0].id: 587 is outside [0, 586]");
    expectError("[[camera.fake_tags]]\nid = 1\nposition = [0.0, 0.9]\n", "test.toml:3: camera.fake_tags[0].position:");
    expectError(kObject + "scale = 0\n", "test.toml:7: objects[0].scale:");
    expectError("[environment]\nintensity = 1000\n", "test.toml:2: environment.intensity:");
}

TEST_F(ConfigTest, MissingRequiredKeys)
{
    expectError("[[markers]]\nsize = 0.1\n", "test.toml:1: markers[0].id: required key is missing");
    expectError("[[markers]]\nid = 0\nsize = 0.1\n[[objects]]\nmarker = 0\n",
                "test.toml:4: objects[0].model: required key is missing");
    expectError("[[markers]]\nid = 0\nsize = 0.1\n[[objects]]\nmodel = \"box.glb\"\n",
                "test.toml:4: objects[0].marker: required key is missing");
    expectError("[camera]\nsource = \"y4m\"\n", "test.toml:1: camera.path: required key is missing");
}

TEST_F(ConfigTest, Duplicates)
{
    expectError("[[markers]]\nid = 1\nsize = 0.1\n[[markers]]\nid = 1\nsize = 0.2\n",
                "test.toml:4: markers[1].id: duplicate marker id 1");
    expectError(kObject + "name = \"x\"\n[[objects]]\nname = \"x\"\nmodel = \"box.glb\"\nmarker = 0\n",
                "test.toml:8: objects[1].name: duplicate object name 'x'");
    expectError("[[camera.fake_tags]]\nid = 2\n[[camera.fake_tags]]\nid = 2\n",
                "test.toml:3: camera.fake_tags[1].id: duplicate fake tag id 2");
}

TEST_F(ConfigTest, UnknownMarkerReference)
{
    expectError("[[markers]]\nid = 0\nsize = 0.1\n[[objects]]\nmodel = \"box.glb\"\nmarker = 7\n",
                "test.toml:4: objects[0].marker: marker 7 is not listed in [[markers]]");
}

TEST_F(ConfigTest, MissingFiles)
{
    const std::string m =
        expectError("[[markers]]\nid = 0\nsize = 0.1\n[[objects]]\nmodel = \"nope.glb\"\nmarker = 0\n",
                    "test.toml:5: objects[0].model: no such file: ");
    EXPECT_NE(m.find("nope.glb"), std::string::npos);
    expectError("[environment]\nhdr = \"missing.hdr\"\n", "test.toml:2: environment.hdr: no such file");
    expectError("[camera]\ncalibration = \"cam.yaml\"\n", "test.toml:2: camera.calibration: no such file");
    expectError("[camera]\nsource = \"images\"\npath = \"noframes\"\n", "test.toml:3: camera.path: no such directory");
    expectError("[output]\npath = \"nodir/out.png\"\n", "test.toml:2: output.path: no such directory");
}

TEST_F(ConfigTest, BadValuesFromFixedSets)
{
    expectError("[camera]\nsource = \"v4l3\"\n", "test.toml:2: camera.source: 'v4l3' is not one of fake, y4m, images");
    expectError("[tracking]\nfamily = \"tag99h1\"\n", "test.toml:2: tracking.family: 'tag99h1' is not one of");
    expectError("[output]\nsink = \"screen\"\n", "test.toml:2: output.sink:");
    expectError("[output]\npath = \"out.jpg\"\n", "test.toml:2: output.path:");
    std::ofstream(dir_ / "model.obj") << "v 0 0 0\n";
    expectError("[[markers]]\nid = 0\nsize = 0.1\n[[objects]]\nmodel = \"model.obj\"\nmarker = 0\n",
                "test.toml:4: objects[0].model:");
    expectError("log_level = \"loud\"\n", "test.toml:1: log_level:");
}

TEST_F(ConfigTest, LoadConfigReportsUnreadableFiles)
{
    try {
        (void)loadConfig(dir_ / "absent.toml");
        FAIL() << "no error";
    } catch (const InputError& e) {
        EXPECT_EQ(std::string(e.what()).rfind((dir_ / "absent.toml").string() + ": cannot read", 0), 0u) << e.what();
    }
    std::ofstream(dir_ / "scene.toml") << "[camera]\nwidth = 1\n";
    try {
        (void)loadConfig(dir_ / "scene.toml");
        FAIL() << "no error";
    } catch (const InputError& e) {
        EXPECT_EQ(std::string(e.what()).rfind((dir_ / "scene.toml").string() + ":2: camera.width", 0), 0u) << e.what();
    }
}

TEST_F(ConfigTest, CameraFormatAndControls)
{
    const Config c = parse("[camera]\nformat = \"mjpeg\"\n[camera.controls]\nexposure_us = 8000\ngain = 40\n"
                           "white_balance_k = \"auto\"\npower_line_hz = 50\n");
    EXPECT_EQ(c.camera.format, "mjpeg");
    EXPECT_EQ(c.camera.controls.exposureUs, 8000);
    EXPECT_EQ(c.camera.controls.gain, 40);
    EXPECT_EQ(c.camera.controls.whiteBalanceK, CameraControlsConfig::kAuto);
    EXPECT_EQ(c.camera.controls.powerLineHz, 50);
    const Config d = parse("[camera.controls]\nexposure_us = \"auto\"\nwhite_balance_k = 4500\n");
    EXPECT_EQ(d.camera.format, "auto");
    EXPECT_EQ(d.camera.controls.exposureUs, CameraControlsConfig::kAuto);
    EXPECT_EQ(d.camera.controls.whiteBalanceK, 4500);
    EXPECT_FALSE(d.camera.controls.gain.has_value());
    EXPECT_FALSE(d.camera.controls.powerLineHz.has_value());

    expectError("[camera]\nformat = \"rgb24\"\n", "test.toml:2: camera.format:");
    EXPECT_EQ(d.camera.zeroCopy, "auto");
    EXPECT_EQ(parse("[camera]\nzero_copy = \"off\"\n").camera.zeroCopy, "off");
    expectError("[camera]\nzero_copy = \"on\"\n", "test.toml:2: camera.zero_copy:");
    expectError("[camera.controls]\nexposure_us = \"manual\"\n", "test.toml:2: camera.controls.exposure_us:");
    expectError("[camera.controls]\nexposure_us = 0\n", "test.toml:2: camera.controls.exposure_us: 0 is outside");
    expectError("[camera.controls]\nexposure_us = 1.5\n",
                "test.toml:2: camera.controls.exposure_us: expected \"auto\" or an integer");
    expectError("[camera.controls]\ngain = -1\n", "test.toml:2: camera.controls.gain:");
    expectError("[camera.controls]\nwhite_balance_k = 100\n", "test.toml:2: camera.controls.white_balance_k:");
    expectError("[camera.controls]\npower_line_hz = 55\n",
                "test.toml:2: camera.controls.power_line_hz: 55 must be 0 (off), 50 or 60");
    expectError("[camera.controls]\nfocus = 3\n", "test.toml:2: camera.controls.focus: unknown key");
}

} // namespace
} // namespace lumar
