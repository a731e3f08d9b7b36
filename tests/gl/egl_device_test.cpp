// The headless display on an EGL device (EGL_EXT_platform_device): what NVIDIA's driver offers
// instead of Mesa's surfaceless platform. Here Mesa lists its software device, which must
// render exactly what the surfaceless platform renders (both are llvmpipe).
#include <cstdlib>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "core/error.h"
#include "gl_test_support.h"
#include "gles_renderer/assets/builtin_shapes.h"
#include "gles_renderer/gl/egl_context.h"

namespace lumar {
namespace {

// The index of Mesa's software EGL device, if EGL lists one.
std::optional<int> softwareDevice()
{
    const std::vector<std::string> devices = EglDisplay::deviceExtensions();
    for (size_t i = 0; i < devices.size(); ++i)
        if ((" " + devices[i] + " ").find(" EGL_MESA_device_software ") != std::string::npos)
            return int(i);
    return std::nullopt;
}

// A lit sphere over a camera image, rendered on `display` (null: the default headless one).
Image8 renderSphere(const std::shared_ptr<EglDisplay>& display)
{
    RenderOptions options;
    options.display = display;
    std::unique_ptr<SceneRenderer> renderer = SceneRenderer::create(96, 64, options);
    renderer->setEnvironment(test::uniformEnvironment(0.8f), 1.0f);
    const DrawItem item{renderer->addModel(makeBuiltinShape("sphere")), test::translation(0, 0, 1)};
    const Image8 camera = test::solidImage(96, 64, 40, 90, 160);
    renderer->render(camera, defaultIntrinsics(96, 64), {&item, 1});
    Image8 out;
    renderer->readback(out);
    return out;
}

TEST(EglDevice, TheSoftwareDeviceRendersWhatTheSurfacelessPlatformRenders)
{
    const std::optional<int> index = softwareDevice();
    if (!index)
        GTEST_SKIP() << "EGL lists no software device (EGL_EXT_device_enumeration, EGL_MESA_device_software)";
    std::shared_ptr<EglDisplay> device;
    try {
        device = EglDisplay::device(*index);
    } catch (const RuntimeError& e) {
        GTEST_SKIP() << e.what();
    }
    EXPECT_EQ(device->platformName(), "device");
    const Image8 onDevice = renderSphere(device);
    const Image8 onDefault = renderSphere(nullptr);
    ASSERT_EQ(onDevice.data.size(), onDefault.data.size());
    EXPECT_EQ(test::maxCodeDifference(onDevice, onDefault), 0);
    // The sphere is drawn: its centre is not the camera image's colour.
    const size_t centre = (size_t(32) * 96 + 48) * 3;
    EXPECT_NE(onDevice.data[centre + 2], 160);
}

// Without another vendor's device the default stays Mesa's surfaceless platform (CI: llvmpipe).
TEST(EglDevice, WithoutAHardwareDeviceTheHeadlessDisplayIsSurfaceless)
{
    const std::vector<std::string> devices = EglDisplay::deviceExtensions();
    for (const std::string& extensions : devices)
        if ((" " + extensions + " ").find(" EGL_MESA_device_software ") == std::string::npos)
            GTEST_SKIP() << "this machine has a hardware EGL device";
    std::shared_ptr<EglDisplay> display;
    try {
        display = EglDisplay::surfaceless();
    } catch (const RuntimeError& e) {
        GTEST_SKIP() << e.what();
    }
    EXPECT_EQ(display->platformName(), "surfaceless");
}

// ctest runs each test in its own process: no other holder keeps a headless display alive.
TEST(EglDevice, AnUnknownForcedPlatformIsRefusedByName)
{
    ASSERT_EQ(setenv("LUMAR_EGL_PLATFORM", "vulkan", 1), 0);
    try {
        (void)EglDisplay::surfaceless();
        ADD_FAILURE() << "no error";
    } catch (const RuntimeError& e) {
        EXPECT_NE(std::string(e.what()).find("LUMAR_EGL_PLATFORM"), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find("vulkan"), std::string::npos) << e.what();
    }
    unsetenv("LUMAR_EGL_PLATFORM");
}

TEST(EglDevice, ForcingTheDevicePlatformUsesTheFirstDevice)
{
    if (EglDisplay::deviceExtensions().empty())
        GTEST_SKIP() << "EGL lists no device";
    ASSERT_EQ(setenv("LUMAR_EGL_PLATFORM", "device", 1), 0);
    std::shared_ptr<EglDisplay> display;
    try {
        display = EglDisplay::surfaceless();
    } catch (const RuntimeError& e) {
        unsetenv("LUMAR_EGL_PLATFORM");
        GTEST_SKIP() << e.what();
    }
    unsetenv("LUMAR_EGL_PLATFORM");
    EXPECT_EQ(display->platformName(), "device");
    const EglContext context(display);
    EXPECT_EQ(eglGetCurrentContext(), context.handle());
}

TEST(EglDevice, AnIndexPastTheDevicesIsRefused)
{
    const int count = int(EglDisplay::deviceExtensions().size());
    EXPECT_THROW((void)EglDisplay::device(count), RuntimeError);
    EXPECT_THROW((void)EglDisplay::device(-1), RuntimeError);
}

} // namespace
} // namespace lumar
