#include <limits>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "tracking/detection_json.h"

namespace lumar {
namespace {

TagDetection handMadeDetection()
{
    TagDetection d;
    d.id = 3;
    d.hamming = 1;
    d.decisionMargin = 57.25;
    d.corners = {glm::dvec2{1.5, 2.25}, {100.125, 2.0}, {100.0, 99.5}, {0.000001234, -0.5}};
    d.hasPose = true;
    // glm is column-major: R[column][row]. Rows (0.1 0.2 0.3), (0.4 0.5 0.6), (0.7 0.8 0.9).
    d.cameraFromMarker.R = glm::dmat3(glm::dvec3(0.1, 0.4, 0.7), glm::dvec3(0.2, 0.5, 0.8), glm::dvec3(0.3, 0.6, 0.9));
    d.cameraFromMarker.t = {0.1, -0.2, 1.23456789012};
    d.reprojectionErrorPx = 0.05;
    return d;
}

TEST(DetectionJson, ExactLineForHandMadeDetections)
{
    TagDetection withoutPose;
    withoutPose.id = 7;
    withoutPose.decisionMargin = 12.5;
    withoutPose.corners = {glm::dvec2{10, 20}, {30, 20}, {30, 0}, {10, 0}};
    const std::string json = detectionsToJson("frames/a.png", {handMadeDetection(), withoutPose});
    EXPECT_EQ(json, "{\"file\":\"frames/a.png\",\"detections\":["
                    "{\"id\":3,\"hamming\":1,\"margin\":57.25,"
                    "\"corners\":[[1.5,2.25],[100.125,2],[100,99.5],[1.234e-06,-0.5]],"
                    "\"R\":[[0.1,0.2,0.3],[0.4,0.5,0.6],[0.7,0.8,0.9]],\"t\":[0.1,-0.2,1.23456789]},"
                    "{\"id\":7,\"hamming\":0,\"margin\":12.5,\"corners\":[[10,20],[30,20],[30,0],[10,0]]}]}");
    EXPECT_EQ(json.find('\n'), std::string::npos);
}

TEST(DetectionJson, NoDetections)
{
    EXPECT_EQ(detectionsToJson("x.png", {}), "{\"file\":\"x.png\",\"detections\":[]}");
}

TEST(DetectionJson, PrecisionIsSixDigitsForPixelsAndNineForThePose)
{
    TagDetection d = handMadeDetection();
    d.corners[0] = {1234.56789, 0.1234567};
    d.cameraFromMarker.t = {0.123456789123, 0, 0};
    const std::string json = detectionsToJson("f", {d});
    EXPECT_NE(json.find("[[1234.57,0.123457]"), std::string::npos) << json;
    EXPECT_NE(json.find("\"t\":[0.123456789,0,0]"), std::string::npos) << json;
}

// The "file" field as written for `name`, quotes included.
std::string fileField(const std::string& name)
{
    const std::string json = detectionsToJson(name, {});
    const std::string prefix = "{\"file\":", suffix = ",\"detections\":[]}";
    EXPECT_EQ(json.rfind(prefix, 0), 0u) << json;
    EXPECT_GE(json.size(), prefix.size() + suffix.size()) << json;
    EXPECT_EQ(json.substr(json.size() - suffix.size()), suffix) << json;
    return json.substr(prefix.size(), json.size() - prefix.size() - suffix.size());
}

TEST(DetectionJson, FileNamesAreEscaped)
{
    EXPECT_EQ(fileField("a\"b\\c"), "\"a\\\"b\\\\c\"");
    EXPECT_EQ(fileField("tab\tnl\ncr\r"), "\"tab\\tnl\\ncr\\r\"");
    EXPECT_EQ(fileField(std::string("\x01\x1f", 2)), "\"\\u0001\\u001f\"");
    EXPECT_EQ(fileField("caf\xc3\xa9 \xe2\x82\xac \xf0\x9f\x98\x80"), "\"caf\xc3\xa9 \xe2\x82\xac \xf0\x9f\x98\x80\"");
    // Invalid UTF-8 (a lone continuation byte, a truncated sequence, an overlong form and a
    // UTF-16 surrogate) cannot go into JSON as is: each ill-formed sequence becomes U+FFFD,
    // written in UTF-8 (EF BF BD) as nlohmann's error_handler_t::replace does, not as \ufffd.
    const std::string replacement = "\xef\xbf\xbd";
    EXPECT_EQ(fileField("a\x80z"), "\"a" + replacement + "z\"");
    EXPECT_EQ(fileField("a\xc3"), "\"a" + replacement + "\"");
    EXPECT_EQ(fileField("\xc0\xaf"), "\"" + replacement + replacement + "\"");
    EXPECT_EQ(fileField("\xed\xa0\x80"), "\"" + replacement + replacement + replacement + "\"");
    // A character cut short is one ill-formed sequence (Unicode's "maximal subpart"), not two.
    EXPECT_EQ(fileField("a\xe2\x82z"), "\"a" + replacement + "z\"");
    EXPECT_EQ(detectionsToJson("we\"ird\n.png", {}), "{\"file\":\"we\\\"ird\\n.png\",\"detections\":[]}");
}

TEST(DetectionJson, AnyFileNameParsesBackToItsUtf8Text)
{
    for (const std::string name : {"we\"ird\n.png", "back\\slash\t.png", "caf\xc3\xa9.png", "\x7f\x01.png"}) {
        const auto j = nlohmann::json::parse(detectionsToJson(name, {}));
        EXPECT_EQ(j["file"], name);
    }
    const auto invalid = nlohmann::json::parse(detectionsToJson("bad\xff\xc3(.png", {}));
    EXPECT_EQ(invalid["file"], "bad\xef\xbf\xbd\xef\xbf\xbd(.png");
}

TEST(DetectionJson, NonFiniteNumbersBecomeNull)
{
    TagDetection d = handMadeDetection();
    d.decisionMargin = std::numeric_limits<double>::quiet_NaN();
    const std::string json = detectionsToJson("f", {d});
    EXPECT_NE(json.find("\"margin\":null"), std::string::npos) << json;
}

} // namespace
} // namespace lumar
