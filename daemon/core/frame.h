// One captured camera frame as it travels through the pipeline.
#pragma once

#include <cstdint>

#include "core/image.h"
#include "core/ycbcr_image.h"

namespace lumar {

struct Frame {
    uint64_t sequence = 0;   // counts from 0 at stream start; gaps are drops
    int64_t timestampNs = 0; // CLOCK_MONOTONIC at capture (fake sources: sequence / fps)
    Image8 rgb;              // 3 channels, sRGB; left stale when `ycbcr` holds the frame
    Image8 luma;             // 1 channel, what the tracker reads
    // The camera's own YCbCr planes, filled instead of `rgb` by a source asked for them
    // (V4l2Options::rawYcbcr); empty() otherwise. The renderer converts them on the GPU.
    YCbCrImage ycbcr;
};

} // namespace lumar
