// lumar probe: what this machine offers lumar — cameras and their formats, the EGL/GLES
// implementation and the extensions that matter, display devices. Informational: it reports
// what is missing instead of failing.
#include <algorithm>
#include <cstdio>
#include <filesystem>

#include "capture/libcamera/libcamera_probe.h"
#include "capture/v4l2/v4l2_probe.h"
#include "commands.h"
#include "core/error.h"
#include "gles_renderer/display/drm_probe.h"
#include "gles_renderer/gl/gl_probe.h"

namespace lumar {
namespace {

void printCameras(const std::vector<std::string>& devices)
{
    std::printf("V4L2 cameras:\n");
    if (devices.empty())
        std::printf("  none (no /dev/video* device)\n");
    for (const std::string& path : devices) {
        const V4l2DeviceInfo info = probeV4l2Device(path);
        if (!info.error.empty()) {
            std::printf("  %s: %s\n", path.c_str(), info.error.c_str());
            continue;
        }
        std::printf("  %s: %s (driver %s, %s)%s\n", path.c_str(), info.card.c_str(), info.driver.c_str(),
                    info.busInfo.c_str(), info.streamingCapture ? "" : " — not a streaming capture device");
        for (const V4l2FormatInfo& format : info.formats) {
            std::printf("    %-4s %s", format.fourcc.c_str(), format.convertible ? "" : "(not used by lumar) ");
            for (const FrameSize& size : format.sizes)
                std::printf(" %ux%u", size.width, size.height);
            std::printf("\n");
        }
    }
}

void printSizes(const std::vector<FrameSize>& sizes, FrameSize minSize, FrameSize maxSize)
{
    for (const FrameSize& size : sizes)
        std::printf(" %ux%u", size.width, size.height);
    if (sizes.empty())
        std::printf(" %ux%u..%ux%u", minSize.width, minSize.height, maxSize.width, maxSize.height);
}

void printLibcameraCameras()
{
    const LibcameraProbeInfo info = probeLibcamera();
    std::printf("libcamera cameras (%s):\n", info.version.c_str());
    if (info.cameras.empty())
        std::printf("  none: %s\n", info.error.c_str());
    for (const LibcameraCameraInfo& camera : info.cameras) {
        std::printf("  %s: %s\n", camera.id.c_str(), camera.model.empty() ? "(no model)" : camera.model.c_str());
        if (!camera.error.empty()) {
            std::printf("    %s\n", camera.error.c_str());
            continue;
        }
        std::printf("    viewfinder default: %s\n", camera.defaultStream.c_str());
        for (const LibcameraFormatInfo& format : camera.formats) {
            std::printf("    %-8s %s", format.pixelFormat.c_str(), format.convertible ? "" : "(not used by lumar) ");
            printSizes(format.sizes, format.minSize, format.maxSize);
            std::printf("\n");
        }
    }
}

void printGraphics()
{
    std::printf("EGL/GLES (headless):\n");
    try {
        const GlInfo gl = probeGl();
        std::printf("  EGL %s (%s) on the %s platform, client APIs: %s\n", gl.eglVersion.c_str(), gl.eglVendor.c_str(),
                    gl.eglPlatform.c_str(), gl.eglClientApis.c_str());
        std::printf("  %s, %s\n  renderer: %s\n", gl.glVersion.c_str(), gl.glslVersion.c_str(), gl.glRenderer.c_str());
        std::printf("  driver: %s%s%s\n", gl.driverName.empty() ? "(not reported)" : gl.driverName.c_str(),
                    gl.drmDevice.empty() ? "" : " on ", gl.drmDevice.c_str());
        std::printf("  camera dmabuf import: %s\n",
                    gl.cameraImport.empty() ? "yes (zero-copy)" : ("no: " + gl.cameraImport).c_str());
        for (const auto* list : {&gl.eglExtensions, &gl.glExtensions})
            for (const auto& [name, present] : *list)
                std::printf("  %-42s %s\n", name.c_str(), present ? "yes" : "no");
    } catch (const RuntimeError& e) {
        std::printf("  unavailable: %s\n", e.what());
    }
}

void printDisplays()
{
    std::printf("DRM devices:\n");
    for (const std::string& line : describeDrmDevices())
        std::printf("%s\n", line.c_str());
}

} // namespace

int probeCommand(const ProbeCommandOptions& options)
{
    std::vector<std::string> devices = listVideoDevices();
    for (const std::string& device : options.devices)
        if (std::find(devices.begin(), devices.end(), device) == devices.end())
            devices.push_back(device);
    printCameras(devices);
    printLibcameraCameras();
    printGraphics();
    printDisplays();
    return kExitOk;
}

} // namespace lumar
