#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <sys/stat.h>

#include "status_file.h"
#include "unit/capture/temp_dir.h"

namespace lumar {
namespace {

RunStatus aStatus()
{
    RunStatus s;
    s.fps = 29.97123;
    s.frames = 1234;
    s.framesWithMarkers = 1000;
    s.objectsDrawn = 2;
    s.markersVisible = {0, 5};
    s.uptimeS = 12.345;
    s.startupMs = 812.34;
    return s;
}

TEST(StatusFile, OneLineWhoseFieldsParseBackWithTheirTypes)
{
    const std::string text = statusJson(aStatus());
    EXPECT_EQ(text.find('\n'), text.size() - 1) << text;
    const auto j = nlohmann::json::parse(text);
    EXPECT_EQ(j["state"], "running");
    EXPECT_NEAR(j["fps"].get<double>(), 29.97, 1e-12);
    EXPECT_TRUE(j["frames"].is_number_integer());
    EXPECT_EQ(j["frames"], 1234);
    EXPECT_EQ(j["frames_with_markers"], 1000);
    EXPECT_EQ(j["objects_drawn"], 2);
    EXPECT_NEAR(j["uptime_s"].get<double>(), 12.3, 1e-12);
    EXPECT_NEAR(j["startup_ms"].get<double>(), 812.3, 1e-12);
    EXPECT_TRUE(j["last_reload_ms"].is_null()) << "not known yet";
    EXPECT_TRUE(j["latency_ms"].is_null()) << "not known yet";
    EXPECT_EQ(j["markers_visible"], nlohmann::json::array({0, 5}));
    EXPECT_EQ(j["camera"], "ok");
    EXPECT_EQ(j["config"], "ok");
}

TEST(StatusFile, LatencyPercentilesOnceKnown)
{
    RunStatus s = aStatus();
    s.latencyP50Ms = 41.26;
    s.latencyP99Ms = 58.04;
    const auto j = nlohmann::json::parse(statusJson(s));
    EXPECT_NEAR(j["latency_ms"]["p50"].get<double>(), 41.3, 1e-12);
    EXPECT_NEAR(j["latency_ms"]["p99"].get<double>(), 58.0, 1e-12);
}

// The soak's leak check (scripts/soak.sh): GL objects alive per kind, absent until given.
TEST(StatusFile, GlObjectCountsOnceGiven)
{
    RunStatus s = aStatus();
    EXPECT_FALSE(nlohmann::json::parse(statusJson(s)).contains("gl_objects"));
    s.glObjects = {{"textures", 31}, {"programs", 12}};
    const auto j = nlohmann::json::parse(statusJson(s));
    EXPECT_EQ(j["gl_objects"], nlohmann::json({{"textures", 31}, {"programs", 12}}));
    EXPECT_EQ(j["config"], "ok");
}

TEST(StatusFile, ReasonsWithQuotesControlsAndInvalidUtf8AreValidJson)
{
    RunStatus s = aStatus();
    s.camera = "unavailable: /dev/video0: \"busy\"\nretrying \\ \t\x01";
    s.config = "rejected: caf\xc3\xa9\x80.toml:3: bad";
    const auto j = nlohmann::json::parse(statusJson(s));
    EXPECT_EQ(j["camera"], s.camera);
    EXPECT_EQ(j["config"], "rejected: caf\xc3\xa9\xef\xbf\xbd.toml:3: bad") << "an invalid byte becomes U+FFFD";
}

TEST(StatusFile, NonFiniteNumbersBecomeNull)
{
    RunStatus s = aStatus();
    s.fps = std::numeric_limits<double>::quiet_NaN();
    s.uptimeS = std::numeric_limits<double>::infinity();
    const auto j = nlohmann::json::parse(statusJson(s));
    EXPECT_TRUE(j["fps"].is_null());
    EXPECT_TRUE(j["uptime_s"].is_null());
}

TEST(StatusFile, ReplacesTheFileWorldReadableWhateverTheUmask)
{
    const test::TempDir dir;
    const StatusFile file(dir / "status.json");
    const mode_t before = ::umask(0077);
    file.write(aStatus());
    RunStatus second = aStatus();
    second.frames = 1235;
    file.write(second);
    ::umask(before);
    const auto j = nlohmann::json::parse(std::ifstream(dir / "status.json"));
    EXPECT_EQ(j["frames"], 1235);
    const auto perms = std::filesystem::status(dir / "status.json").permissions();
    EXPECT_NE(perms & std::filesystem::perms::others_read, std::filesystem::perms::none);
    EXPECT_FALSE(std::filesystem::exists(dir / "status.json.partial"));
}

// The daemon's write: a status that cannot be written (here its directory is missing, as
// when it was removed or is on a full disk) is reported, not thrown, and the next write
// after the cause is gone succeeds.
TEST(StatusFile, AFailedWriteIsReportedNotThrownAndRecovers)
{
    const test::TempDir dir;
    StatusFile file(dir / "gone" / "status.json");
    EXPECT_FALSE(file.writeOrReport(aStatus()));
    EXPECT_FALSE(file.writeOrReport(aStatus()));
    std::filesystem::create_directory(dir / "gone");
    EXPECT_TRUE(file.writeOrReport(aStatus()));
    EXPECT_EQ(nlohmann::json::parse(std::ifstream(dir / "gone" / "status.json"))["frames"], 1234);
}

} // namespace
} // namespace lumar
