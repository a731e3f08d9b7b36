// Choosing and opening the capture source [camera] names: the one place that knows every
// backend (fake, Y4M, image folder, V4L2, libcamera). Its own library so that the backends
// depend on the CaptureSource interface and not the other way round.
#pragma once

#include <memory>

#include "capture/capture_source.h"
#include "config/config.h"

namespace lumar {

// The stream options [camera] asks for.
CameraStreamOptions cameraStreamOptions(const CameraConfig& config);

// Opens the source the config names. Throws InputError for a bad path or file.
std::unique_ptr<CaptureSource> openCaptureSource(const CameraConfig& config);

} // namespace lumar
