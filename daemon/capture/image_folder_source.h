// File playback from a folder of still images (PNG, JPEG, BMP, PPM/PGM), played in file-name
// order at the configured frame rate.
#pragma once

#include <filesystem>
#include <vector>

#include "capture/capture_source.h"

namespace lumar {

class ImageFolderSource final : public CaptureSource {
public:
    // Lists config.path's images (extensions png, jpg, jpeg, bmp, ppm, pgm in any case) and
    // checks that every one decodes to the same size. Throws InputError naming the folder or
    // the offending file.
    explicit ImageFolderSource(const CameraConfig& config);

    bool next(Frame& frame) override; // false after the last image unless config.loop
    [[nodiscard]] int width() const override { return width_; }
    [[nodiscard]] int height() const override { return height_; }
    [[nodiscard]] double fps() const override { return fps_; }
    [[nodiscard]] const std::vector<std::filesystem::path>& files() const { return files_; }

private:
    std::vector<std::filesystem::path> files_;
    int width_ = 0;
    int height_ = 0;
    double fps_ = 0.0;
    bool loop_ = true;
    size_t nextFile_ = 0;
    uint64_t sequence_ = 0;
};

} // namespace lumar
