// The config's [camera.controls] and frame rate mapped to libcamera controls, against fake
// ControlInfoMaps shaped like real cameras' (a Raspberry Pi-like camera with ColourGains but
// no settable ColourTemperature, a UVC-like camera, one with libcamera v0.2's flicker controls,
// one with nothing): what is set, clamping to the advertised range, what is skipped.
#include <cmath>

#include <gtest/gtest.h>
#include <libcamera/control_ids.h>
#include <libcamera/controls.h>

#include "capture/libcamera/libcamera_controls.h"

namespace lumar {
namespace {

namespace controls = libcamera::controls;
using libcamera::ControlInfo;
using libcamera::ControlInfoMap;
using libcamera::ControlList;

// libcamera v0.2's flicker controls, which v0.0.3 does not declare: a camera advertising them
// is recognised by name.
const libcamera::ControlId kFlickerMode(0x10001, "AeFlickerMode", libcamera::ControlTypeInteger32);
const libcamera::ControlId kFlickerPeriod(0x10002, "AeFlickerPeriod", libcamera::ControlTypeInteger32);

// The ids the fake maps use, by number (what ControlInfoMap looks them up by).
const libcamera::ControlIdMap& idMap()
{
    static const libcamera::ControlIdMap map = [] {
        libcamera::ControlIdMap ids = controls::controls;
        ids[kFlickerMode.id()] = &kFlickerMode;
        ids[kFlickerPeriod.id()] = &kFlickerPeriod;
        return ids;
    }();
    return map;
}

ControlInfoMap infoMap(ControlInfoMap::Map entries)
{
    return ControlInfoMap(std::move(entries), idMap());
}

// A sensor with an ISP that has a colour temperature control (like rkisp1 with a newer IPA).
ControlInfoMap isp()
{
    return infoMap({{&controls::AeEnable, ControlInfo(false, true)},
                    {&controls::ExposureTime, ControlInfo(int32_t(100), int32_t(66666))},
                    {&controls::AnalogueGain, ControlInfo(1.0f, 16.0f)},
                    {&controls::AwbEnable, ControlInfo(false, true)},
                    {&controls::ColourTemperature, ControlInfo(int32_t(2000), int32_t(8000))},
                    {&controls::FrameDurationLimits, ControlInfo(int64_t(16666), int64_t(200000))}});
}

ControlList controlsFor(const CameraControlsConfig& config, const ControlInfoMap& info,
                        std::vector<AppliedLibcameraControl>* applied = nullptr)
{
    ControlList list(info);
    auto result = addLibcameraControls(config, info, list, "test-camera");
    if (applied)
        *applied = std::move(result);
    return list;
}

TEST(LibcameraControls, ManualValuesTurnTheAutomaticModesOffAndAreClamped)
{
    CameraControlsConfig config;
    config.exposureUs = 10000;
    config.gain = 400;
    config.whiteBalanceK = 4500;
    std::vector<AppliedLibcameraControl> applied;
    const ControlList list = controlsFor(config, isp(), &applied);
    EXPECT_EQ(list.get(controls::AeEnable), std::optional<bool>(false));
    EXPECT_EQ(list.get(controls::ExposureTime), std::optional<int32_t>(10000));
    EXPECT_EQ(list.get(controls::AnalogueGain), std::optional<float>(4.0f)); // gain 100 = 1.0x
    EXPECT_EQ(list.get(controls::AwbEnable), std::optional<bool>(false));
    EXPECT_EQ(list.get(controls::ColourTemperature), std::optional<int32_t>(4500));
    EXPECT_FALSE(list.contains(controls::ColourGains.id()));
    // In order: each automatic mode before the manual value it unlocks.
    ASSERT_EQ(applied.size(), 5u);
    EXPECT_EQ(applied[0].name, "exposure_us (AeEnable)");
    EXPECT_EQ(applied[1].name, "exposure_us (ExposureTime)");
    EXPECT_EQ(applied[1].value, "10000");
    EXPECT_EQ(applied[3].name, "white_balance_k (AwbEnable)");

    config.exposureUs = 1'000'000; // above the 66.666 ms the camera allows
    config.gain = 5000;            // 50x, above 16x
    config.whiteBalanceK = 1000;   // below 2000 K
    const ControlList clamped = controlsFor(config, isp());
    EXPECT_EQ(clamped.get(controls::ExposureTime), std::optional<int32_t>(66666));
    EXPECT_EQ(clamped.get(controls::AnalogueGain), std::optional<float>(16.0f));
    EXPECT_EQ(clamped.get(controls::ColourTemperature), std::optional<int32_t>(2000));
    config.gain = 0; // below 1x
    EXPECT_EQ(controlsFor(config, isp()).get(controls::AnalogueGain), std::optional<float>(1.0f));
}

TEST(LibcameraControls, AutoSwitchesTheAlgorithmsOnAndSetsNoManualValue)
{
    CameraControlsConfig config;
    config.exposureUs = CameraControlsConfig::kAuto;
    config.whiteBalanceK = CameraControlsConfig::kAuto;
    const ControlList list = controlsFor(config, isp());
    EXPECT_EQ(list.get(controls::AeEnable), std::optional<bool>(true));
    EXPECT_EQ(list.get(controls::AwbEnable), std::optional<bool>(true));
    EXPECT_FALSE(list.contains(controls::ExposureTime.id()));
    EXPECT_FALSE(list.contains(controls::ColourTemperature.id()));
    EXPECT_EQ(list.size(), 2u);
}

TEST(LibcameraControls, NothingAskedNothingSet)
{
    EXPECT_TRUE(controlsFor(CameraControlsConfig{}, isp()).empty());
}

// A Raspberry Pi-like camera: ColourTemperature is reported in metadata but not settable;
// manual white balance is ColourGains.
TEST(LibcameraControls, WithoutColourTemperatureAKelvinValueBecomesColourGains)
{
    const ControlInfoMap raspberry =
        infoMap({{&controls::AwbEnable, ControlInfo(false, true)}, {&controls::ColourGains, ControlInfo(0.0f, 32.0f)}});
    CameraControlsConfig config;
    config.whiteBalanceK = 3000; // tungsten: reddish light, so less red and more blue gain
    const ControlList list = controlsFor(config, raspberry);
    EXPECT_EQ(list.get(controls::AwbEnable), std::optional<bool>(false));
    ASSERT_TRUE(list.contains(controls::ColourGains.id()));
    const libcamera::ControlValue& value = list.get(controls::ColourGains.id());
    ASSERT_TRUE(value.isArray());
    const auto gains = value.get<libcamera::Span<const float>>();
    ASSERT_EQ(gains.size(), 2u);
    const std::array<float, 2> expected = colourGainsForTemperature(3000);
    EXPECT_FLOAT_EQ(gains[0], expected[0]);
    EXPECT_FLOAT_EQ(gains[1], expected[1]);
    EXPECT_LT(gains[0], 1.0f);
    EXPECT_GT(gains[1], 1.0f);

    // 1000 K asks for a blue gain far beyond the camera's 32: clamped into its range.
    config.whiteBalanceK = 1000;
    // The span points into the list's value: keep the list alive while it is read.
    const ControlList extremeList = controlsFor(config, raspberry);
    const auto extreme = extremeList.get(controls::ColourGains.id()).get<libcamera::Span<const float>>();
    EXPECT_LE(extreme[1], 32.0f);
    EXPECT_GE(extreme[0], 0.0f);
}

TEST(LibcameraControls, BlackBodyGainsAreNeutralAtDaylightAndFollowTheTemperature)
{
    // The Planckian 6500 K lies a little off D65 (sRGB's white): close to, not exactly, 1.
    const auto daylight = colourGainsForTemperature(6500);
    EXPECT_NEAR(daylight[0], 1.0, 0.08);
    EXPECT_NEAR(daylight[1], 1.0, 0.08);
    float lastRed = 0.0f;
    float lastBlue = 1e9f;
    for (int kelvin = 2000; kelvin <= 20000; kelvin += 500) {
        const auto gains = colourGainsForTemperature(kelvin);
        EXPECT_TRUE(std::isfinite(gains[0]) && std::isfinite(gains[1])) << kelvin;
        EXPECT_GT(gains[0], lastRed) << kelvin; // warmer light, less red gain
        EXPECT_LT(gains[1], lastBlue) << kelvin;
        lastRed = gains[0];
        lastBlue = gains[1];
    }
    const auto cold = colourGainsForTemperature(500); // clamped to the fit's 1667 K
    EXPECT_TRUE(std::isfinite(cold[0]) && std::isfinite(cold[1]));
}

TEST(LibcameraControls, ControlsTheCameraLacksAreSkipped)
{
    // A UVC-like camera: exposure and gain, no white balance, no flicker control.
    const ControlInfoMap uvc = infoMap({{&controls::AeEnable, ControlInfo(false, true)},
                                        {&controls::ExposureTime, ControlInfo(int32_t(100), int32_t(500000))},
                                        {&controls::AnalogueGain, ControlInfo(1.0f, 8.0f)}});
    CameraControlsConfig config;
    config.exposureUs = 20000;
    config.whiteBalanceK = 5000;
    config.powerLineHz = 50;
    std::vector<AppliedLibcameraControl> applied;
    const ControlList list = controlsFor(config, uvc, &applied);
    EXPECT_EQ(list.get(controls::ExposureTime), std::optional<int32_t>(20000));
    EXPECT_EQ(list.size(), 2u); // AeEnable and ExposureTime only
    EXPECT_EQ(applied.size(), 2u);

    // A camera with no controls at all: nothing is set, nothing throws.
    config.gain = 100;
    config.exposureUs = CameraControlsConfig::kAuto;
    EXPECT_TRUE(controlsFor(config, infoMap({})).empty());

    // An AeEnable that can only be on: manual exposure cannot turn it off, the time is still set.
    const ControlInfoMap alwaysAuto = infoMap({{&controls::AeEnable, ControlInfo(true)},
                                               {&controls::ExposureTime, ControlInfo(int32_t(100), int32_t(500000))}});
    config = {};
    config.exposureUs = 5000;
    const ControlList partial = controlsFor(config, alwaysAuto);
    EXPECT_FALSE(partial.contains(controls::AeEnable.id()));
    EXPECT_EQ(partial.get(controls::ExposureTime), std::optional<int32_t>(5000));
}

TEST(LibcameraControls, PowerLineFrequencyUsesTheFlickerControlsWhereTheCameraHasThem)
{
    const ControlInfoMap flicker = infoMap({{&kFlickerMode, ControlInfo(int32_t(0), int32_t(2))},
                                            {&kFlickerPeriod, ControlInfo(int32_t(100), int32_t(1000000))}});
    CameraControlsConfig config;
    config.powerLineHz = 50;
    ControlList list = controlsFor(config, flicker);
    EXPECT_EQ(list.get(kFlickerMode.id()).get<int32_t>(), 1);       // FlickerManual
    EXPECT_EQ(list.get(kFlickerPeriod.id()).get<int32_t>(), 10000); // 100 Hz flicker
    config.powerLineHz = 60;
    list = controlsFor(config, flicker);
    EXPECT_EQ(list.get(kFlickerPeriod.id()).get<int32_t>(), 8333);
    config.powerLineHz = 0;
    list = controlsFor(config, flicker);
    EXPECT_EQ(list.get(kFlickerMode.id()).get<int32_t>(), 0); // FlickerOff
    EXPECT_FALSE(list.contains(kFlickerPeriod.id()));

    // A mode without a period cannot be manual: nothing is set.
    config.powerLineHz = 50;
    EXPECT_TRUE(controlsFor(config, infoMap({{&kFlickerMode, ControlInfo(int32_t(0), int32_t(2))}})).empty());
}

TEST(LibcameraControls, FrameDurationIsTheRequestedRateWithinTheCamerasRange)
{
    const ControlInfoMap camera = isp(); // 16.666 ms .. 200 ms
    EXPECT_EQ(frameDurationFor(30.0, camera), (std::array<int64_t, 2>{33333, 33333}));
    EXPECT_EQ(frameDurationFor(120.0, camera), (std::array<int64_t, 2>{16666, 16666})); // at most 60 fps
    EXPECT_EQ(frameDurationFor(2.0, camera), (std::array<int64_t, 2>{200000, 200000})); // at least 5 fps
    EXPECT_EQ(frameDurationFor(0.0, camera), std::nullopt);
    EXPECT_EQ(frameDurationFor(30.0, infoMap({})), std::nullopt);
}

} // namespace
} // namespace lumar
