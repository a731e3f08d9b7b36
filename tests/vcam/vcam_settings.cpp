#include "vcam/vcam_settings.h"

#include <algorithm>
#include <charconv>
#include <cstdlib>
#include <string_view>

#include <linux/videodev2.h>

namespace lumar::vcam {
namespace {

void readInteger(const char* name, int64_t& value)
{
    const char* text = std::getenv(name);
    if (text == nullptr) {
        return;
    }
    const std::string_view view(text);
    int64_t parsed = 0;
    const auto [end, error] = std::from_chars(view.data(), view.data() + view.size(), parsed);
    if (error == std::errc() && end == view.data() + view.size()) {
        value = parsed;
    }
}

// "WxH" with even sides in [16, 4096]; anything else leaves the size as it was.
void readSize(std::string_view text, uint32_t& width, uint32_t& height)
{
    const size_t x = text.find('x');
    if (x == std::string_view::npos) {
        return;
    }
    uint32_t w = 0;
    uint32_t h = 0;
    const auto [wEnd, wError] = std::from_chars(text.data(), text.data() + x, w);
    const auto [hEnd, hError] = std::from_chars(text.data() + x + 1, text.data() + text.size(), h);
    const auto valid = [](uint32_t v) { return v >= 16 && v <= 4096 && v % 2 == 0; };
    if (wError == std::errc() && hError == std::errc() && wEnd == text.data() + x &&
        hEnd == text.data() + text.size() && valid(w) && valid(h)) {
        width = w;
        height = h;
    }
}

// "YUYV,GREY" → the fourccs this device knows, in the order given.
std::vector<uint32_t> readFormats(const char* text)
{
    std::vector<uint32_t> formats;
    std::string_view rest(text);
    while (!rest.empty()) {
        const size_t comma = rest.find(',');
        const std::string_view name = rest.substr(0, comma);
        for (uint32_t known : {V4L2_PIX_FMT_YUYV, V4L2_PIX_FMT_NV12, V4L2_PIX_FMT_MJPEG, V4L2_PIX_FMT_GREY}) {
            const char code[4] = {char(known & 0xff), char((known >> 8) & 0xff), char((known >> 16) & 0xff),
                                  char(known >> 24)};
            if (name == std::string_view(code, 4)) {
                formats.push_back(known);
            }
        }
        rest = comma == std::string_view::npos ? std::string_view() : rest.substr(comma + 1);
    }
    return formats;
}

} // namespace

Settings settingsFromEnvironment()
{
    Settings settings;
    if (const char* path = std::getenv("LUMAR_VCAM_DEVICE"); path != nullptr && *path != '\0') {
        settings.devicePath = path;
    }
    if (const char* encoding = std::getenv("LUMAR_VCAM_YCBCR_ENC"); encoding != nullptr) {
        settings.bt709 = std::string_view(encoding) == "709";
    }
    if (const char* range = std::getenv("LUMAR_VCAM_QUANTIZATION"); range != nullptr) {
        settings.fullRange = std::string_view(range) == "full";
    }
    if (const char* formats = std::getenv("LUMAR_VCAM_FORMATS"); formats != nullptr) {
        settings.pixelFormats = readFormats(formats);
    }
    if (settings.pixelFormats.empty()) {
        settings.pixelFormats = {V4L2_PIX_FMT_YUYV, V4L2_PIX_FMT_NV12, V4L2_PIX_FMT_MJPEG, V4L2_PIX_FMT_GREY};
    }
    readInteger("LUMAR_VCAM_FAULT_UNPLUG_AT", settings.unplugAt);
    readInteger("LUMAR_VCAM_FAULT_STALL_AT", settings.stallAt);
    readInteger("LUMAR_VCAM_FAULT_STALL_MS", settings.stallMs);
    readInteger("LUMAR_VCAM_FAULT_DROP_EVERY", settings.dropEvery);
    readInteger("LUMAR_VCAM_FAULT_SHORT_EVERY", settings.shortEvery);
    readInteger("LUMAR_VCAM_FAULT_CORRUPT_EVERY", settings.corruptEvery);
    if (const char* paced = std::getenv("LUMAR_VCAM_PACED"); paced != nullptr) {
        settings.paced = std::string_view(paced) == "1";
    }
    readInteger("LUMAR_VCAM_JPEG_QUALITY", settings.jpegQuality);
    settings.jpegQuality = std::clamp<int64_t>(settings.jpegQuality, 1, 100);
    readInteger("LUMAR_VCAM_SOURCE_CHANGE_AT", settings.sourceChangeAt);
    if (const char* size = std::getenv("LUMAR_VCAM_SOURCE_CHANGE_SIZE"); size != nullptr) {
        readSize(size, settings.sourceChangeWidth, settings.sourceChangeHeight);
    }
    return settings;
}

} // namespace lumar::vcam
