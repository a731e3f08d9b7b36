#include "capture/capture_source.h"

#include "capture/fake_camera.h"
#include "capture/image_folder_source.h"
#include "capture/y4m_source.h"
#include "core/error.h"

namespace lumar {

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
    throw InputError("camera.source: unknown source '" + config.source + "' (expected fake, y4m or images)");
}

} // namespace lumar
