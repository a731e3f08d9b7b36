// The check every consumer of a frame in memory makes before reading it: the background's
// upload and the camera image's reduction both read every pixel of the frame.
#pragma once

#include <string>

#include "core/error.h"
#include "core/image.h"

namespace lumar {

// Throws InputError naming `what` when `rgb` is not `width` x `height` x 3 (its data included).
inline void checkRgbFrame(const Image8& rgb, int width, int height, const char* what)
{
    if (rgb.width != width || rgb.height != height || rgb.channels != 3 ||
        rgb.data.size() != size_t(width) * size_t(height) * 3)
        throw InputError(std::string(what) + " is " + std::to_string(rgb.width) + "x" + std::to_string(rgb.height) +
                         "x" + std::to_string(rgb.channels) + ", the renderer needs " + std::to_string(width) + "x" +
                         std::to_string(height) + "x3");
}

} // namespace lumar
