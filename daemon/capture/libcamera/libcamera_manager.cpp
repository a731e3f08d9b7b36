#include "capture/libcamera/libcamera_manager.h"

#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <mutex>

#include <libcamera/camera_manager.h>

#include "capture/reconnecting_source.h"
#include "core/log.h"

namespace lumar {
namespace {

// libcamera logs to stderr on its own (an INFO banner, a WARN when no IPA modules are
// installed). Unless the user asked for its logs, keep only its errors: lumar reports what
// matters itself. The variable is read when libcamera's logger is first created, which is
// the manager's construction, so it is set once before that.
void quietLibcameraLogging()
{
    static std::once_flag once;
    std::call_once(once, [] { ::setenv("LIBCAMERA_LOG_LEVELS", "*:ERROR", /*overwrite=*/0); });
}

// Stops, then deletes: the manager's destructor would stop it too, but stopping explicitly
// keeps the order visible (every camera object is gone once the last handle is released).
struct StopAndDelete {
    void operator()(libcamera::CameraManager* manager) const
    {
        manager->stop();
        delete manager;
    }
};

} // namespace

std::shared_ptr<libcamera::CameraManager> acquireCameraManager()
{
    static std::mutex mutex;
    static std::weak_ptr<libcamera::CameraManager> shared;
    const std::lock_guard lock(mutex);
    if (auto existing = shared.lock()) {
        return existing;
    }
    quietLibcameraLogging();
    auto manager = std::make_unique<libcamera::CameraManager>();
    const int error = manager->start();
    if (error != 0) {
        // Not started: the plain destructor is the right cleanup.
        throw CameraUnavailable("libcamera: the camera manager failed to start: " + std::string(std::strerror(-error)) +
                                " (" + libcameraVersionText() + ", " + std::to_string(countMediaDevices()) +
                                " media devices in /dev)");
    }
    std::shared_ptr<libcamera::CameraManager> started(manager.release(), StopAndDelete{});
    shared = started;
    LUMAR_LOG(Capture, Debug) << libcameraVersionText() << " started";
    return started;
}

std::string libcameraVersionText()
{
    return "libcamera " + libcamera::CameraManager::version();
}

int countMediaDevices()
{
    int count = 0;
    std::error_code ec;
    for (const auto& entry : std::filesystem::directory_iterator("/dev", ec)) {
        if (entry.path().filename().string().rfind("media", 0) == 0) {
            ++count;
        }
    }
    return count;
}

std::string noLibcameraCamerasMessage()
{
    return "libcamera: no cameras found (" + libcameraVersionText() + ", " + std::to_string(countMediaDevices()) +
           " media devices in /dev)";
}

} // namespace lumar
