#include "capture/image_folder_source.h"

#include <algorithm>
#include <array>
#include <cctype>
#include <cstring>
#include <memory>
#include <string>
#include <system_error>

#include <stb_image.h>

#include "capture/colour_conversion.h"
#include "core/error.h"
#include "core/log.h"

namespace lumar {
namespace {

bool isImageFile(const std::filesystem::path& file)
{
    static constexpr std::array<std::string_view, 6> kExtensions{".png", ".jpg", ".jpeg", ".bmp", ".ppm", ".pgm"};
    std::string ext = file.extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return char(std::tolower(c)); });
    return std::find(kExtensions.begin(), kExtensions.end(), ext) != kExtensions.end();
}

std::string failureReason()
{
    const char* reason = stbi_failure_reason();
    return reason ? reason : "unknown reason";
}

struct StbiDeleter {
    void operator()(stbi_uc* pixels) const { stbi_image_free(pixels); }
};

} // namespace

ImageFolderSource::ImageFolderSource(const CameraConfig& config) : fps_(config.fps), loop_(config.loop)
{
    const std::string folder = config.path.string();
    if (!(fps_ > 0.0)) {
        throw InputError("camera.fps: must be positive for an image folder, got " + std::to_string(fps_));
    }
    std::error_code ec;
    if (!std::filesystem::is_directory(config.path, ec)) {
        throw InputError(folder + ": not a folder of images");
    }
    for (std::filesystem::directory_iterator it(config.path, ec), end; !ec && it != end; it.increment(ec)) {
        if (it->is_regular_file(ec) && isImageFile(it->path())) {
            files_.push_back(it->path());
        }
    }
    if (ec) {
        throw InputError(folder + ": cannot list the folder: " + ec.message());
    }
    if (files_.empty()) {
        throw InputError(folder + ": no images (.png, .jpg, .jpeg, .bmp, .ppm, .pgm) in the folder");
    }
    std::sort(files_.begin(), files_.end(),
              [](const auto& a, const auto& b) { return a.filename().string() < b.filename().string(); });

    // Check every file up front (stbi_info reads only the header) so a bad file fails at
    // start-up, not minutes into playback.
    for (const auto& file : files_) {
        int w = 0;
        int h = 0;
        int channels = 0;
        if (!stbi_info(file.string().c_str(), &w, &h, &channels)) {
            throw InputError(file.string() + ": cannot decode the image: " + failureReason());
        }
        if (file == files_.front()) {
            width_ = w;
            height_ = h;
        } else if (w != width_ || h != height_) {
            throw InputError(file.string() + ": size " + std::to_string(w) + "x" + std::to_string(h) +
                             " differs from " + files_.front().filename().string() + "'s " + std::to_string(width_) +
                             "x" + std::to_string(height_));
        }
    }
    LUMAR_LOG(Capture, Info) << "image folder " << folder << ": " << files_.size() << " images of " << width_ << "x"
                             << height_ << " at " << fps_ << " fps";
}

bool ImageFolderSource::next(Frame& frame)
{
    if (nextFile_ == files_.size()) {
        if (!loop_) {
            return false;
        }
        nextFile_ = 0;
    }
    const std::filesystem::path& file = files_[nextFile_];
    int w = 0;
    int h = 0;
    int channels = 0;
    const std::unique_ptr<stbi_uc, StbiDeleter> pixels(stbi_load(file.string().c_str(), &w, &h, &channels, 3));
    if (!pixels) {
        throw InputError(file.string() + ": cannot decode the image: " + failureReason());
    }
    if (w != width_ || h != height_) {
        // The file changed since the folder was opened.
        throw InputError(file.string() + ": size " + std::to_string(w) + "x" + std::to_string(h) +
                         " differs from the folder's " + std::to_string(width_) + "x" + std::to_string(height_));
    }
    frame.rgb.reshape(w, h, 3);
    std::memcpy(frame.rgb.data.data(), pixels.get(), frame.rgb.data.size());
    lumaFromRgb(frame.rgb, frame.luma);
    frame.sequence = sequence_;
    frame.timestampNs = int64_t(double(sequence_) * 1e9 / fps_ + 0.5);
    ++sequence_;
    ++nextFile_;
    return true;
}

} // namespace lumar
