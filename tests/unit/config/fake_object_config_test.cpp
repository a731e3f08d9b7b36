// [[camera.fake_objects]], camera.exposure and the fake camera's environment: what parses,
// and one-line "FILE:LINE: key: what is wrong" errors for each kind of mistake.
#include <filesystem>
#include <fstream>

#include <gtest/gtest.h>

#include "config/config.h"
#include "config_fixture.h"

namespace lumar {
namespace {

namespace fs = std::filesystem;

class FakeObjectConfigTest : public test::ConfigFixture {
protected:
    void SetUp() override
    {
        test::ConfigFixture::SetUp();
        fs::copy_file(fs::path(LUMAR_TEST_DATA_DIR) / "apriltag/tag36h11/tag36_11_00000.png", dir_ / "label.png");
        std::ofstream(dir_ / "broken.png") << "this is not an image\n";
        std::ofstream(dir_ / "env.hdr") << "#?RADIANCE\n";
    }
};

const std::string kTags = "[[camera.fake_tags]]\nid = 0\n[[camera.fake_tags]]\nid = 5\nposition = [0.3, 0.0]\n";

TEST_F(FakeObjectConfigTest, ReadsBoxesAndCylinders)
{
    const Config c = parse(kTags + "[camera]\nexposure = 0.5\n"
                                   "[[camera.fake_objects]]\nshape = \"box\"\ntag = 0\nsize = [0.1, 0.2, 0.3]\n"
                                   "offset = [0.05, -0.1]\nheading = 30\ncolor = [0.8, 0.2, 0.1]\n"
                                   "[[camera.fake_objects]]\nshape = \"cylinder\"\ntag = 5\nsize = [0.06, 0.06, 0.12]\n"
                                   "texture = \"label.png\"\n");
    EXPECT_DOUBLE_EQ(c.camera.exposure, 0.5);
    ASSERT_EQ(c.camera.fakeObjects.size(), 2u);
    const FakeObjectConfig& box = c.camera.fakeObjects[0];
    EXPECT_EQ(box.shape, "box");
    EXPECT_EQ(box.tag, 0);
    EXPECT_EQ(box.size, glm::dvec3(0.1, 0.2, 0.3));
    EXPECT_EQ(box.offset, glm::dvec2(0.05, -0.1));
    EXPECT_DOUBLE_EQ(box.headingDeg, 30.0);
    EXPECT_EQ(box.color, glm::dvec3(0.8, 0.2, 0.1));
    EXPECT_TRUE(box.texture.empty());
    const FakeObjectConfig& cylinder = c.camera.fakeObjects[1];
    EXPECT_EQ(cylinder.shape, "cylinder");
    EXPECT_EQ(cylinder.tag, 5);
    EXPECT_EQ(cylinder.texture, dir_ / "label.png"); // relative to the file
}

TEST_F(FakeObjectConfigTest, DefaultsAreNoObjectsExposureOneAndNoEnvironment)
{
    const Config c = parse("");
    EXPECT_TRUE(c.camera.fakeObjects.empty());
    EXPECT_DOUBLE_EQ(c.camera.exposure, 1.0);
    EXPECT_TRUE(c.camera.fakeEnvironment.empty());
}

TEST_F(FakeObjectConfigTest, TheFakeCameraGetsTheEnvironmentTheObjectsAreLitBy)
{
    const Config c = parse("[environment]\nhdr = \"env.hdr\"\nintensity = 2.5\n");
    EXPECT_EQ(c.camera.fakeEnvironment, dir_ / "env.hdr");
    EXPECT_DOUBLE_EQ(c.camera.fakeEnvironmentIntensity, 2.5);
    // Another source has no use for it (and a reload must not reopen a real camera for it).
    const Config v4l2 = parse("[camera]\nsource = \"v4l2\"\n[environment]\nhdr = \"env.hdr\"\n");
    EXPECT_TRUE(v4l2.camera.fakeEnvironment.empty());
}

TEST_F(FakeObjectConfigTest, ShippedDefaultStandsABoxBesideTagZero)
{
    const Config c = defaultConfig();
    EXPECT_TRUE(fs::is_regular_file(c.camera.fakeEnvironment)) << c.camera.fakeEnvironment;
    ASSERT_EQ(c.camera.fakeObjects.size(), 1u);
    const FakeObjectConfig& box = c.camera.fakeObjects[0];
    EXPECT_EQ(box.tag, 0);
    // Beside the tag, not on it: the footprint clears the tag's white frame (0.2 m square).
    const double clearance =
        std::max(std::abs(box.offset.x) - 0.5 * box.size.x, std::abs(box.offset.y) - 0.5 * box.size.y);
    EXPECT_GT(clearance, 0.1);
    // The documented example says the same.
    const Config example = loadConfig(fs::path(LUMAR_SOURCE_DIR) / "daemon/assets/lumar.toml");
    EXPECT_EQ(example.camera.fakeObjects, c.camera.fakeObjects);
    EXPECT_EQ(example.camera.exposure, c.camera.exposure);
    EXPECT_EQ(fs::weakly_canonical(example.camera.fakeEnvironment), fs::weakly_canonical(c.camera.fakeEnvironment));
}

TEST_F(FakeObjectConfigTest, RejectsBadObjects)
{
    const std::string head = kTags + "[[camera.fake_objects]]\n";
    expectError(head + "tag = 7\nsize = [0.1, 0.1, 0.1]\ncolor = [0.5, 0.5, 0.5]\n",
                "test.toml:7: camera.fake_objects[0].tag: tag 7 is not in camera.fake_tags");
    expectError(head + "size = [0.1, 0.1, 0.1]\ncolor = [0.5, 0.5, 0.5]\n",
                "test.toml:6: camera.fake_objects[0].tag: required key is missing");
    expectError(head + "tag = 0\nsize = [0.1, 0.0, 0.1]\ncolor = [0.5, 0.5, 0.5]\n",
                "test.toml:8: camera.fake_objects[0].size: each side must be in (0, 2] metres");
    expectError(head + "tag = 0\nsize = [0.1, -0.1, 0.1]\ncolor = [0.5, 0.5, 0.5]\n",
                "test.toml:8: camera.fake_objects[0].size: each side must be in (0, 2] metres");
    expectError(head + "tag = 0\nsize = [0.1, nan, 0.1]\ncolor = [0.5, 0.5, 0.5]\n",
                "test.toml:8: camera.fake_objects[0].size: expected an array of 3 numbers");
    expectError(head + "tag = 0\nsize = [0.1, 0.1, inf]\ncolor = [0.5, 0.5, 0.5]\n",
                "test.toml:8: camera.fake_objects[0].size: expected an array of 3 numbers");
    expectError(head + "tag = 0\ncolor = [0.5, 0.5, 0.5]\n",
                "test.toml:6: camera.fake_objects[0].size: required key is missing");
    expectError(head + "shape = \"cylinder\"\ntag = 0\nsize = [0.1, 0.2, 0.1]\ncolor = [0.5, 0.5, 0.5]\n",
                "test.toml:9: camera.fake_objects[0].size: a cylinder's x and y are its diameter");
    expectError(head + "tag = 0\nsize = [0.1, 0.1, 0.1]\ncolor = [0.5, 1.5, 0.5]\n",
                "test.toml:9: camera.fake_objects[0].color: each channel must be in [0, 1]");
    expectError(head + "tag = 0\nsize = [0.1, 0.1, 0.1]\ncolor = [-0.1, 0.5, 0.5]\n",
                "test.toml:9: camera.fake_objects[0].color: each channel must be in [0, 1]");
    expectError(head + "tag = 0\nsize = [0.1, 0.1, 0.1]\ncolor = [0.5, 0.5, 0.5]\ntexture = \"label.png\"\n",
                "test.toml:10: camera.fake_objects[0].texture: give either color or texture, not both");
    expectError(head + "tag = 0\nsize = [0.1, 0.1, 0.1]\n",
                "test.toml:6: camera.fake_objects[0].color: missing: give color (linear albedo) or texture");
    const std::string broken = (dir_ / "broken.png").string();
    expectError(head + "tag = 0\nsize = [0.1, 0.1, 0.1]\ntexture = \"broken.png\"\n",
                "test.toml:9: camera.fake_objects[0].texture: " + broken + ": cannot read");
    expectError(head + "tag = 0\nsize = [0.1, 0.1, 0.1]\ntexture = \"missing.png\"\n",
                "test.toml:9: camera.fake_objects[0].texture: no such file: " + (dir_ / "missing.png").string());
    expectError(head + "shape = \"sphere\"\ntag = 0\nsize = [0.1, 0.1, 0.1]\ncolor = [0.5, 0.5, 0.5]\n",
                "test.toml:7: camera.fake_objects[0].shape: 'sphere' is not one of box, cylinder");
    expectError(head + "tag = 0\nsize = [0.1, 0.1, 0.1]\ncolor = [0.5, 0.5, 0.5]\nheight = 2\n",
                "test.toml:10: camera.fake_objects[0].height: unknown key");
}

TEST_F(FakeObjectConfigTest, RejectsBadExposure)
{
    expectError("[camera]\nexposure = 0\n", "test.toml:2: camera.exposure: 0 is outside (0, ");
    expectError("[camera]\nexposure = -1\n", "test.toml:2: camera.exposure:");
    expectError("[camera]\nexposure = inf\n", "test.toml:2: camera.exposure:");
    expectError("[camera]\nexposure = nan\n", "test.toml:2: camera.exposure:");
}

} // namespace
} // namespace lumar
