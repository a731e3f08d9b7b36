// One captured camera frame as it travels through the pipeline.
#pragma once

#include <cstdint>

#include "core/image.h"
#include "core/ycbcr_image.h"

namespace lumar {

struct Frame {
    uint64_t sequence = 0;   // counts from 0 at stream start; gaps are drops
    int64_t timestampNs = 0; // CLOCK_MONOTONIC at capture (fake sources: sequence / fps)
    // CLOCK_MONOTONIC when the frame was captured, where capture-to-present latency starts:
    // a camera's timestamp; for the fake camera and files, the moment the frame was drawn or
    // decoded (their timestampNs is sequence / fps); 0: unknown (PrefetchingSource stamps it).
    int64_t capturedNs = 0;
    Image8 rgb;  // 3 channels, sRGB; left stale when `ycbcr` holds the frame
    Image8 luma; // 1 channel, what the tracker reads
    // The camera's own YCbCr planes, filled instead of `rgb` by a source asked for them
    // (V4l2Options::rawYcbcr); empty() otherwise. The renderer converts them on the GPU.
    YCbCrImage ycbcr;
};

} // namespace lumar
