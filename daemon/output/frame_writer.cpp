#include "output/frame_writer.h"

#include <algorithm>
#include <cctype>
#include <cstring>
#include <string>

#include <stb_image.h>
#include <stb_image_write.h>

#include "core/error.h"
#include "output/png_still_writer.h"
#include "output/y4m_writer.h"

namespace lumar {
namespace {

std::string lowerExtension(const std::filesystem::path& file)
{
    std::string ext = file.extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return char(std::tolower(c)); });
    return ext;
}

struct StbiDeleter {
    void operator()(stbi_uc* pixels) const { stbi_image_free(pixels); }
};

} // namespace

std::unique_ptr<FrameWriter> openFrameWriter(const std::filesystem::path& file, double fps)
{
    const std::string ext = lowerExtension(file);
    if (ext == ".png") {
        return std::make_unique<PngStillWriter>(file);
    }
    if (ext == ".y4m") {
        return std::make_unique<Y4mWriter>(file, fps);
    }
    throw InputError(file.string() + ": unsupported output type '" + ext + "' (expected .png or .y4m)");
}

void writePng(const std::filesystem::path& file, const Image8& image)
{
    if (image.width <= 0 || image.height <= 0 || image.channels < 1 || image.channels > 4 ||
        image.data.size() != size_t(image.width) * size_t(image.height) * size_t(image.channels)) {
        throw RuntimeError(file.string() + ": cannot write an empty or malformed image as PNG");
    }
    const int stride = image.width * image.channels;
    if (!stbi_write_png(file.c_str(), image.width, image.height, image.channels, image.data.data(), stride)) {
        throw RuntimeError(file.string() + ": cannot write the PNG (unwritable path or disk full)");
    }
}

Image8 readImage(const std::filesystem::path& file, int channels)
{
    if (channels < 1 || channels > 4) {
        throw InputError(file.string() + ": cannot read an image as " + std::to_string(channels) + " channels");
    }
    int w = 0;
    int h = 0;
    int fileChannels = 0;
    const std::unique_ptr<stbi_uc, StbiDeleter> pixels(stbi_load(file.c_str(), &w, &h, &fileChannels, channels));
    if (!pixels) {
        const char* reason = stbi_failure_reason();
        throw InputError(file.string() + ": cannot read the image: " + (reason ? reason : "unknown reason"));
    }
    Image8 image(w, h, channels);
    std::memcpy(image.data.data(), pixels.get(), image.data.size());
    return image;
}

} // namespace lumar
