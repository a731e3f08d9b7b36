// Camera calibration files in OpenCV FileStorage YAML (read by calibration_yaml.h, written by
// OpenCV): camera_matrix (3x3),
// distortion_coefficients (1x5 or 5x1), image_width, image_height.
#pragma once

#include <filesystem>
#include <optional>

#include "core/camera_model.h"

namespace lumar {

// Throws InputError "FILE: what is wrong" for a missing, malformed or implausible file.
CameraIntrinsics loadCalibration(const std::filesystem::path& file);

// Throws RuntimeError when the file cannot be written. A calibration's reprojection RMS, when
// given, is recorded as avg_reprojection_error (OpenCV's sample's key; loadCalibration ignores it).
void saveCalibration(const std::filesystem::path& file, const CameraIntrinsics& intrinsics,
                     std::optional<double> reprojectionRmsPx = std::nullopt);

} // namespace lumar
