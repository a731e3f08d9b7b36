#include "capture/factory/capture_factory.h"

#include "capture/fake_camera.h"
#include "capture/image_folder_source.h"
#include "capture/libcamera/libcamera_source.h"
#include "capture/reconnecting_source.h"
#include "capture/v4l2/v4l2_format.h"
#include "capture/v4l2/v4l2_source.h"
#include "capture/y4m_source.h"
#include "core/error.h"

namespace lumar {

CameraStreamOptions cameraStreamOptions(const CameraConfig& config)
{
    CameraStreamOptions options;
    options.width = config.width;
    options.height = config.height;
    options.fps = config.fps;
    options.bufferCount = config.buffers;
    options.frameTimeoutMs = config.timeoutMs;
    options.controls = config.controls;
    // The renderer converts NV12/YUYV on the GPU unless the operator asks for the CPU.
    options.rawYcbcr = config.convert == "gpu";
    // The frames borrow the camera's buffers (dmabufs for the renderer to import).
    options.zeroCopy = config.zeroCopy == "auto";
    return options;
}

std::unique_ptr<CaptureSource> openCaptureSource(const CameraConfig& config)
{
    if (config.source == "fake") {
        return std::make_unique<FakeCamera>(config);
    }
    if (config.source == "y4m") {
        return std::make_unique<Y4mSource>(config);
    }
    if (config.source == "images") {
        return std::make_unique<ImageFolderSource>(config);
    }
    if (config.source == "v4l2") {
        V4l2Options options;
        static_cast<CameraStreamOptions&>(options) = cameraStreamOptions(config);
        options.device = config.device;
        options.pixelFormat = pixelFormatFromName(config.format);
        // The pipeline sizes its renderer and intrinsics once; a resolution change reopens.
        options.followResolutionChanges = false;
        // A camera can be unplugged or hang; it is reopened in place when it comes back.
        return std::make_unique<ReconnectingSource>([options] { return std::make_unique<V4l2Source>(options); },
                                                    options.device);
    }
    if (config.source == "libcamera") {
        LibcameraOptions options;
        static_cast<CameraStreamOptions&>(options) = cameraStreamOptions(config);
        options.cameraId = config.device;
        options.format = config.format;
        LibcameraSource::checkFormatName(config.format); // before any camera is opened: bad input
        // Reopened in place after a disconnect or a hang, like a V4L2 camera.
        return std::make_unique<ReconnectingSource>([options] { return std::make_unique<LibcameraSource>(options); },
                                                    "libcamera");
    }
    throw InputError("camera.source: unknown source '" + config.source +
                     "' (expected fake, y4m, images, v4l2 or libcamera)");
}

} // namespace lumar
