// [environment] source and match_exposure: where the real environment comes from, and
// whether the virtual objects follow the camera's exposure.
#include <filesystem>
#include <fstream>

#include <gtest/gtest.h>

#include "config_fixture.h"

namespace lumar::test {
namespace {

class EnvironmentSourceConfig : public ConfigFixture {
protected:
    void SetUp() override
    {
        ConfigFixture::SetUp();
        std::ofstream(dir_ / "env.hdr") << "not read by the parser";
    }
};

TEST_F(EnvironmentSourceConfig, DefaultsToTheHdrWithExposureMatching)
{
    const Config c = parse("");
    EXPECT_EQ(c.environment.source, "hdr");
    EXPECT_TRUE(c.environment.matchExposure);
    EXPECT_EQ(defaultConfig().environment.source, "hdr");
    EXPECT_TRUE(defaultConfig().environment.matchExposure);
}

TEST_F(EnvironmentSourceConfig, ReadsEachSource)
{
    EXPECT_EQ(parse("[environment]\nsource = \"hdr\"\n").environment.source, "hdr");
    // The camera alone needs no file.
    EXPECT_EQ(parse("[environment]\nsource = \"camera\"\n").environment.source, "camera");
    const Config both = parse("[environment]\nhdr = \"env.hdr\"\nsource = \"camera+hdr\"\nmatch_exposure = false\n");
    EXPECT_EQ(both.environment.source, "camera+hdr");
    EXPECT_EQ(both.environment.hdr, dir_ / "env.hdr");
    EXPECT_FALSE(both.environment.matchExposure);
}

TEST_F(EnvironmentSourceConfig, RejectsAnUnknownSource)
{
    const std::string message =
        expectError("[environment]\n\nsource = \"webcam\"\n", "test.toml:3: environment.source");
    EXPECT_NE(message.find("webcam"), std::string::npos) << message;
}

TEST_F(EnvironmentSourceConfig, CameraOverHdrNeedsAnHdr)
{
    const std::string message =
        expectError("[environment]\nsource = \"camera+hdr\"\n", "test.toml:2: environment.source");
    EXPECT_NE(message.find("hdr"), std::string::npos) << message;
}

TEST_F(EnvironmentSourceConfig, MatchExposureIsABoolean)
{
    expectError("[environment]\nmatch_exposure = \"yes\"\n", "test.toml:2: environment.match_exposure");
}

} // namespace
} // namespace lumar::test
