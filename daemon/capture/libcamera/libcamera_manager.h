// The process's one libcamera CameraManager. libcamera allows a single manager per process (a
// second one aborts), and it must outlive every camera, request and buffer taken from it; so
// the capture source and `lumar probe` share it through a handle, started on first use and
// stopped when the last holder lets go.
#pragma once

#include <memory>
#include <string>

namespace libcamera {
class CameraManager;
}

namespace lumar {

// The started manager. Throws CameraUnavailable when libcamera cannot start (no device
// enumerator, no permission on the media devices).
std::shared_ptr<libcamera::CameraManager> acquireCameraManager();

// "libcamera v0.0.3", for messages and `lumar probe`.
std::string libcameraVersionText();

// How many /dev/media* nodes exist: libcamera finds cameras through them only, so none at
// all is the usual reason it lists no cameras.
int countMediaDevices();

// The one-line reason to report when the manager lists no cameras, e.g.
// "libcamera: no cameras found (libcamera v0.0.3, 0 media devices in /dev)".
std::string noLibcameraCamerasMessage();

} // namespace lumar
