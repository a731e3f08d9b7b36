// One captured camera frame as it travels through the pipeline.
#pragma once

#include <cstdint>

#include "core/image.h"

namespace lumar {

struct Frame {
    uint64_t sequence = 0;   // counts from 0 at stream start; gaps are drops
    int64_t timestampNs = 0; // CLOCK_MONOTONIC at capture (fake sources: sequence / fps)
    Image8 rgb;              // 3 channels, sRGB
    Image8 luma;             // 1 channel, what the tracker reads
};

} // namespace lumar
