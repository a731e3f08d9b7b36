#include "capture/libcamera/libcamera_probe.h"

#include <libcamera/camera.h>
#include <libcamera/camera_manager.h>
#include <libcamera/property_ids.h>
#include <libcamera/stream.h>

#include "capture/libcamera/libcamera_frame.h"
#include "capture/libcamera/libcamera_manager.h"
#include "core/error.h"

namespace lumar {
namespace {

FrameSize frameSizeOf(const libcamera::Size& size)
{
    return {size.width, size.height};
}

LibcameraCameraInfo probeCamera(libcamera::Camera& camera)
{
    LibcameraCameraInfo info;
    info.id = camera.id();
    info.model = camera.properties().get(libcamera::properties::Model).value_or("");
    // Generating a configuration needs no acquire(): probing works while another process
    // streams from the camera.
    const std::unique_ptr<libcamera::CameraConfiguration> configuration =
        camera.generateConfiguration({libcamera::StreamRole::Viewfinder});
    if (!configuration || configuration->empty()) {
        info.error = "no viewfinder stream";
        return info;
    }
    const libcamera::StreamConfiguration& stream = configuration->at(0);
    info.defaultStream = stream.toString();
    const libcamera::StreamFormats& formats = stream.formats();
    for (const libcamera::PixelFormat& pixelFormat : formats.pixelformats()) {
        LibcameraFormatInfo format;
        format.pixelFormat = pixelFormat.toString();
        format.convertible = isConvertibleLibcameraFormat(pixelFormat);
        for (const libcamera::Size& size : formats.sizes(pixelFormat)) {
            format.sizes.push_back(frameSizeOf(size));
        }
        const libcamera::SizeRange range = formats.range(pixelFormat);
        format.minSize = frameSizeOf(range.min);
        format.maxSize = frameSizeOf(range.max);
        info.formats.push_back(std::move(format));
    }
    return info;
}

} // namespace

LibcameraProbeInfo probeLibcamera()
{
    LibcameraProbeInfo info;
    info.version = libcameraVersionText();
    try {
        const std::shared_ptr<libcamera::CameraManager> manager = acquireCameraManager();
        for (const std::shared_ptr<libcamera::Camera>& camera : manager->cameras()) {
            info.cameras.push_back(probeCamera(*camera));
        }
        if (info.cameras.empty()) {
            info.error = noLibcameraCamerasMessage();
        }
    } catch (const RuntimeError& e) {
        info.error = e.what();
    }
    return info;
}

} // namespace lumar
